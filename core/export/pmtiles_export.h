#pragma once
// A map (MBTiles or folder pyramid, or one of its layers) as a PMTiles v3
// archive: tiles in Hilbert order, identical tiles stored once, the map's
// metadata as the archive's JSON metadata.
#include <cstdint>
#include <functional>
#include <string>

#include "core/export/pmtiles_writer.h"
#include "core/tiles/tile_store.h"

namespace seamap {

// `source` names the map in errors. `on_tile(done, total)` is called after
// each tile. Throws InputError(source, 0, "tiles", ...) for a map without
// tiles or an unknown tile format, InputError(path, ...) for I/O errors.
PmtilesSummary ExportPmtiles(const TileStore& from, const std::string& source, const std::string& path,
                             const std::function<void(int64_t, int64_t)>& on_tile = {});

}  // namespace seamap
