#pragma once
// One zoom level of a map as a Cloud-Optimised GeoTIFF (GDAL's COG driver):
// Web Mercator (EPSG:3857), the level's tile-aligned extent, lossless
// DEFLATE, 256-pixel blocks, overviews down to one block. GDAL reads the
// map through a dataset whose blocks are the map's tiles, decoded on demand,
// so memory stays bounded by GDAL's block cache, not by the mission. Works
// for any zoom (GDAL's own MBTiles driver stops at 22).
#include <functional>
#include <string>

#include "core/tiles/tile_store.h"

namespace seamap {

struct GeotiffOptions {
  int zoom = -1;                       // -1: the map's deepest level
  std::string resampling = "AVERAGE";  // overviews: GDAL's name (NEAREST, AVERAGE, BILINEAR, CUBIC...)
  int threads = 0;                     // compression threads; 0 = all CPUs
  void Check() const;                  // InputError("--zoom" / "--resampling", ...)
};

struct GeotiffSummary {
  int zoom = 0;
  int width_px = 0, height_px = 0, bands = 0;
  int tiles = 0;                                            // tiles of the level that hold data
  double west_m = 0, south_m = 0, east_m = 0, north_m = 0;  // EPSG:3857
};

// `source` names the map in errors. on_progress(fraction 0..1).
// Throws InputError(source, 0, "tiles"|"--zoom", ...) for an empty map or a
// zoom it lacks, InputError(path, 0, "output", ...) when GDAL cannot write.
GeotiffSummary ExportGeotiff(const TileStore& from, const std::string& source, const std::string& path,
                             const GeotiffOptions& options, const std::function<void(double)>& on_progress = {});

}  // namespace seamap
