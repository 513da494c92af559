#pragma once
// Web Mercator (EPSG:3857) XYZ tile arithmetic, as Leaflet and every web map
// uses it: global pixel coordinates at zoom z run from (0,0) at the north-west
// corner (lon -180, lat 85.051) to tile_size * 2^z at the south-east.
#include <cstddef>
#include <cstdint>

#include "core/geo/lat_lon.h"

namespace seamap {

constexpr double kWebMercatorMaxLat = 85.0511287798066;
constexpr double kEarthCircumference = 40075016.685578488;  // 2*pi*6378137 m

struct GlobalPixel {
  double x = 0;
  double y = 0;
};

// Geographic position to global pixel coordinates at `zoom`.
GlobalPixel LatLonToPixel(LatLon ll, int zoom, int tile_size);
LatLon PixelToLatLon(GlobalPixel px, int zoom, int tile_size);

// Ground metres per pixel at latitude `lat` and `zoom`.
double MetersPerPixel(double lat, int zoom, int tile_size);

// The zoom whose pixel size at `lat` is nearest (in log scale) to `gsd_m`.
int ZoomForGroundSampleDistance(double gsd_m, double lat, int tile_size);

struct TileId {
  int z = 0;
  int x = 0;
  int y = 0;  // XYZ row, 0 at the north
  bool operator==(const TileId& o) const { return z == o.z && x == o.x && y == o.y; }
  bool operator!=(const TileId& o) const { return !(*this == o); }
  bool operator<(const TileId& o) const { return z != o.z ? z < o.z : (x != o.x ? x < o.x : y < o.y); }
  TileId Parent() const { return {z - 1, x >> 1, y >> 1}; }
  int TmsRow() const { return (1 << z) - 1 - y; }  // MBTiles row numbering
};

struct TileIdHash {
  size_t operator()(const TileId& t) const {
    return (static_cast<size_t>(t.z) << 58) ^ (static_cast<size_t>(t.x) << 29) ^ static_cast<size_t>(t.y);
  }
};

// Geographic bounds of a tile.
struct LatLonBounds {
  double west = 0, south = 0, east = 0, north = 0;
};
LatLonBounds TileBounds(TileId t);

}  // namespace seamap
