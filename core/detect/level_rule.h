#pragma once
// The class-aware level rule: which boxes cut by a window's edge are trusted.
// Search windows overlap by one tile, so an object no larger than a tile lies
// whole in some window of that level. A class whose largest size
// (seamap.class_sizes_m) fits one tile at some searched level is therefore
// seen whole there, and a cut view of it is a piece: a long pipe cut by a
// zoom-25 window taken for an anchor, half a tyre taken for a rock. Those
// cut views are dropped before the merge; classes of unknown size (0), or too
// large for every searched level, keep them.
#include <vector>

#include "core/detect/merge.h"

namespace seamap {

// Per class, the finest of `zooms` at which its largest size fits one tile of
// `tile_size` px at latitude `lat_deg`; -1 when no searched level holds it
// whole or its size is unknown.
std::vector<int> WholeViewZooms(const std::vector<double>& class_sizes_m, const std::vector<int>& zooms, double lat_deg,
                                int tile_size);

// Removes the truncated boxes of classes with a whole view (whole_view_zoom
// >= 0); returns how many were removed. Boxes of classes outside the table are kept.
int DropCutViews(const std::vector<int>& whole_view_zoom, std::vector<RawDetection>* raw);

}  // namespace seamap
