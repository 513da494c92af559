#pragma once
// One zoom level of a map as a Cloud-Optimised GeoTIFF (GDAL's COG driver):
// Web Mercator (EPSG:3857), the level's tile-aligned extent, lossless
// DEFLATE, 256-pixel blocks, overviews down to one block. GDAL reads the
// map through a dataset whose blocks are the map's tiles, decoded on demand,
// so memory stays bounded by GDAL's block cache, not by the mission. Works
// for any zoom (GDAL's own MBTiles driver stops at 22).
#include <functional>
#include <optional>
#include <string>

#include "core/geo/web_mercator.h"
#include "core/tiles/tile_store.h"

namespace seamap {

struct GeotiffOptions {
  int zoom = -1;                       // -1: the map's deepest level
  std::optional<LatLonBounds> bounds;  // --bounds: only the level's tiles touching these (degrees)
  bool allow_sparse = false;           // --allow-sparse: write a huge raster that is mostly empty anyway
  std::string resampling = "AVERAGE";  // overviews: GDAL's name (NEAREST, AVERAGE, BILINEAR, CUBIC...)
  int threads = 0;                     // compression threads; 0 = all CPUs
  void Check() const;                  // InputError("--zoom" / "--resampling" / "--bounds", ...)
};

// "W,S,E,N" in degrees (west, south, east, north). Throws InputError("--bounds", ...)
// naming what is wrong, quoting at most 100 characters of the text.
LatLonBounds ParseGeotiffBounds(const std::string& text);

// A raster of more than this many pixels of which less than kSparseMaxFilledShare
// of the tiles hold data (a frame placed kilometres off, say) is refused unless
// allow_sparse: GDAL would spend minutes to hours and gigabytes on its emptiness
// (measured: 145 gigapixels at ~47 MB/s of overview temp).
// Measured: a 197-megapixel, 99.9 % empty one took 24 s and 426 MB on a loaded 2-core VM.
constexpr double kSparseRasterPixels = 67108864.0;  // 2^26: 1,024 tiles of 256 px
constexpr double kSparseMaxFilledShare = 0.5;

struct GeotiffSummary {
  int zoom = 0;
  int width_px = 0, height_px = 0, bands = 0;
  int tiles = 0;                                            // tiles of the level that hold data
  double west_m = 0, south_m = 0, east_m = 0, north_m = 0;  // EPSG:3857
};

// `source` names the map in errors. on_progress(fraction 0..1); an exception it
// throws (Ctrl-C) stops GDAL, and is rethrown once the partial file and GDAL's
// temporary overviews (`path`.ovr.tmp) are removed: a failed export leaves nothing.
// Throws InputError(source, 0, "tiles"|"--zoom", ...) for an empty map or a
// zoom it lacks, InputError("--zoom/--bounds", ...) for a huge, mostly empty raster
// (its size, the main part's bounds, a coarser zoom that fits),
// InputError(path, 0, "output", ...) when GDAL cannot write.
GeotiffSummary ExportGeotiff(const TileStore& from, const std::string& source, const std::string& path,
                             const GeotiffOptions& options, const std::function<void(double)>& on_progress = {});

}  // namespace seamap
