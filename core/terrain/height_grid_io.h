#pragma once
// A HeightGrid (height_grid.h) as a GeoTIFF, through GDAL, so that gdalinfo,
// QGIS and other GIS tools read it: what the simulator writes as
// truth/terrain.tif, what `export --dem` writes and `build --terrain-file`
// reads.
//
// File layout written:
//   band 1  "height_m": float32 metres up (the grid's datum), nodata -32767;
//   band 2  "sigma_m":  float32 1-sigma of band 1 (only with write_sigma);
//   metadata SEAMAP_HEIGHT_DATUM = "sea_surface" | "vehicle"
//            (HeightGrid::has_depth_datum; missing means sea_surface);
//   DEFLATE compressed, tiled, with average overviews when larger than a tile.
//
// The grid lives in the mission's local frame, a transverse Mercator centred
// on the mission origin (core/geo/local_frame.h). Written in that CRS the
// file holds the grid's own cells, exactly; in UTM or EPSG:3857 it is
// reprojected (bilinear) onto a north-up grid of about the same cell size.
#include <string>

#include "core/geo/lat_lon.h"
#include "core/terrain/height_grid.h"

namespace seamap {

enum class HeightGridCrs {
  kLocalTmerc,   // +proj=tmerc centred on the origin: the grid's own cells
  kUtm,          // the WGS84 UTM zone of the origin (EPSG:326xx/327xx)
  kWebMercator,  // EPSG:3857, as the map tiles
};

struct HeightGridGeotiffOptions {
  HeightGridCrs crs = HeightGridCrs::kLocalTmerc;
  bool write_sigma = false;  // sigma_m as band 2 (needs a sigma_m of the grid's size)
  bool overviews = true;
};

// "+proj=tmerc ... +datum=WGS84": the mission's local frame as GDAL/PROJ spell it.
std::string LocalTmercProj4(LatLon origin);

// Writes (replacing) `path`. NaN heights become nodata. Throws InputError
// naming the file when the grid is empty or the file cannot be written.
void WriteHeightGridGeotiff(const HeightGrid& grid, LatLon origin, const std::string& path,
                            const HeightGridGeotiffOptions& options = {});

// Reads a height raster in any CRS GDAL knows into the local frame of
// `origin`: a file already in that local tmerc, north-up with square pixels,
// is read cell for cell; anything else is reprojected (bilinear) by GDAL's
// warper onto a local north-up grid of about the source's resolution.
// Nodata and NaN become holes (NaN). Band 2 is read as sigma_m when it is
// described "sigma_m" (our own files); sigma_m is NaN otherwise (unknown).
// Throws InputError naming the file when it cannot be read, is not a
// single-band raster (or height + sigma), or has no CRS or georeference.
HeightGrid ReadHeightGridGeotiff(const std::string& path, LatLon origin);

}  // namespace seamap
