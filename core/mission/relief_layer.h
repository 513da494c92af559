#pragma once
// The height model as a tile layer of the mission: "relief", a colour relief
// with a hillshade (core/terrain/relief_shading.h) in the map's tile format
// (transparent outside the model in PNG and WebP maps; black in JPEG ones),
// from the map's min zoom to the zoom whose pixel is half a grid cell (finer
// zooms gain nothing; the console enlarges). Recorded in the metadata
// (seamap_relief) with the ramp's ends in the user's datum for the legend.
//
// What `build --terrain` calls once the height model is estimated:
//   StoreMissionTerrain(store, {grid, origin}, show_progress);
// It keeps the model in the map (mission_terrain.h) and draws the layer.
#include <string>

#include <nlohmann/json.hpp>

#include "core/mission/mission_terrain.h"
#include "core/tiles/tile_store.h"

namespace seamap {

constexpr const char* kReliefLayer = "relief";

struct ReliefLayerOptions {
  int min_zoom = 0, max_zoom = 0;  // the map's; the layer stops earlier where its cells run out
  int tile_size_px = 256;
  std::string format = "png";  // the map's tile format: png, jpg, webp
};

// The options the map's metadata gives (minzoom, maxzoom, format,
// seamap_tile_size); where it has no zooms yet, those the grid's cell size
// suggests (the zoom of a quarter cell and six coarser).
ReliefLayerOptions ReliefLayerOptionsFor(const TileStore& store, const MissionTerrain& terrain);

// Draws the layer into store->OpenLayer("relief") and records seamap_relief
// (returned: layer, low_m, high_m, datum, minzoom, maxzoom, tiles); no
// flush. Shows a progress bar when asked.
nlohmann::json WriteReliefLayer(TileStore* store, const MissionTerrain& terrain, const ReliefLayerOptions& options,
                                bool show_progress);

// Keeps the height model in the map and draws its relief layer (options from
// the map's metadata), then flushes.
void StoreMissionTerrain(TileStore* store, const MissionTerrain& terrain, bool show_progress);

}  // namespace seamap
