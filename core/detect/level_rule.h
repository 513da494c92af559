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

// Per class, the finest of `zooms` at which its largest size fits one
// search window (WindowTiles tiles a side); -1 when unknown or none. A box of
// a finer level sees at most a stretch of such an object (a 3 m pipe at zoom
// 25, whose windows are 2.6 m): the merge takes its representative at or
// below this level when the cluster has one there (MergeOptions).
std::vector<int> RepresentativeZooms(const std::vector<double>& class_sizes_m, const std::vector<int>& zooms,
                                     double lat_deg, int tile_size);

// Box merging across windows: an object larger than a tile can be cut by
// the edge of every window of a level (windows overlap by one tile), so no
// whole view of it exists there (a 0.96 m anchor or a 1.26 m crate at zoom
// 25 from a survey flown at 1 m, sharp there and blurred at 23). The cut
// views of one class and level that overlap each other (intersection over
// the smaller >= 0.3), from at least two windows, are replaced by their
// union, uncut, with their best score, when its longest side is at most
// 1.25 times the class's largest size (a stretch of a long pipe called an
// anchor in several windows unites into something too long and stays cut).
// Only classes with a whole view (whole_view_zoom >= 0) are stitched (the
// others keep their cut views anyway), and only at levels finer than it (at
// it, some window holds the object whole: a union there is a stretch of a
// larger object, e.g. of a pipe at zoom 23) where its largest size fits a
// window (a 3 m pipe's stretches at zoom 25 stay cut). Returns how many unions were made.
int StitchCutViews(const std::vector<int>& whole_view_zoom, const std::vector<double>& class_sizes_m, double lat_deg,
                   int tile_size, std::vector<RawDetection>* raw);

// Removes the truncated boxes of classes with a whole view (whole_view_zoom
// >= 0); returns how many were removed. Boxes of classes outside the table are kept.
int DropCutViews(const std::vector<int>& whole_view_zoom, std::vector<RawDetection>* raw);

}  // namespace seamap
