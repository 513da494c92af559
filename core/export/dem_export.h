#pragma once
// The mission's height model as a GeoTIFF DEM for QGIS/GDAL (`seamap export
// MAP dem.tif --dem`): one float32 band of heights in metres up, relative to
// the sea surface where the navigation had depth_m, else to the survey's
// mean seabed (core/terrain/height_datum.h); holes and the area outside the
// model are nodata (-32767, as truth/terrain.tif). Cloud-Optimised (GDAL's COG driver, DEFLATE with
// the floating-point predictor) in the model's own grid: the mission's local
// transverse Mercator (core/geo/local_frame.h), so no cell is resampled;
// overviews (AVERAGE, nodata-aware) down to about 32 cells. (The simulator's
// WriteHeightGridGeotiff, core/terrain/height_grid_io.h, writes the stored
// datum, plain GTiff, overviews only past 256 cells; a DEM for a user wants
// the user's datum, a COG, overviews at any size and an atomic write.)
#include <string>

#include "core/mission/mission_terrain.h"

namespace seamap {

struct DemSummary {
  int width_px = 0, height_px = 0;
  int overviews = 0;
  double cell_m = 0;
  double min_m = 0, max_m = 0;  // user heights; 0, 0 for a model of holes only
  std::string datum;            // "sea_surface" or "mean_seabed"
};

constexpr double kDemNodata = -32767;

// Writes through a temporary file renamed into place. Throws
// InputError(path, 0, "output", ...) when GDAL cannot write it.
DemSummary ExportDem(const MissionTerrain& terrain, const std::string& path);

}  // namespace seamap
