#pragma once
// The mission's height model (core/terrain/height_grid.h) kept in its map,
// beside the frames, track and detections: heights and sigma as
// zlib-compressed float32 (little-endian, row-major, heights then sigma) with
// a JSON header giving the geometry, the datum, the local frame's origin and
// the cells' size and CRC-32 (core/tiles TerrainBlob: the MBTiles table
// `terrain`, a folder's terrain.json + terrain.bin). Read back exactly, bit
// for bit; anything that does not add up is an InputError, never a crash.
#include <optional>
#include <string>

#include "core/geo/lat_lon.h"
#include "core/terrain/height_grid.h"
#include "core/tiles/tile_store.h"

namespace seamap {

// The height model and where its local frame is on the Earth.
struct MissionTerrain {
  HeightGrid grid;
  LatLon origin;  // the local frame's origin (core/geo/local_frame.h)
};

// Largest grid kept (rows x cols): 8 bytes a cell, 1 GiB.
constexpr long kMaxTerrainCells = 128L << 20;

// Throws InputError("terrain", 0, field, ...) for a grid that cannot be
// kept: empty, too large, sigma of another size, a cell size or corner that
// is not a positive / finite number.
TerrainBlob EncodeMissionTerrain(const MissionTerrain& terrain);
// `where` names the map in errors: InputError(where, 0, "terrain", ...).
MissionTerrain DecodeMissionTerrain(const TerrainBlob& blob, const std::string& where);

// Stores the height model in the map (replacing any earlier one), in the
// store's open transaction: Flush() commits it.
void WriteMissionTerrain(TileStore* store, const MissionTerrain& terrain);
// The map's height model; nullopt when it has none. Throws InputError naming
// `where` when the stored one cannot be read.
std::optional<MissionTerrain> ReadMissionTerrain(const TileStore& store, const std::string& where);

}  // namespace seamap
