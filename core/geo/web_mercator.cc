#include "core/geo/web_mercator.h"

#include <algorithm>
#include <cmath>

namespace seamap {
namespace {
double WorldSize(int zoom, int tile_size) {
  return std::ldexp(static_cast<double>(tile_size), zoom);
}
}  // namespace

GlobalPixel LatLonToPixel(LatLon ll, int zoom, int tile_size) {
  const double size = WorldSize(zoom, tile_size);
  const double lat = std::clamp(ll.lat, -kWebMercatorMaxLat, kWebMercatorMaxLat) * M_PI / 180.0;
  const double x = (ll.lon + 180.0) / 360.0 * size;
  const double y = (0.5 - std::log(std::tan(M_PI / 4 + lat / 2)) / (2 * M_PI)) * size;
  return {x, y};
}

LatLon PixelToLatLon(GlobalPixel px, int zoom, int tile_size) {
  const double size = WorldSize(zoom, tile_size);
  const double lon = px.x / size * 360.0 - 180.0;
  const double n = M_PI * (1 - 2 * px.y / size);
  const double lat = std::atan(std::sinh(n)) * 180.0 / M_PI;
  return {lat, lon};
}

double MetersPerPixel(double lat, int zoom, int tile_size) {
  return kEarthCircumference * std::cos(lat * M_PI / 180.0) / WorldSize(zoom, tile_size);
}

int ZoomForGroundSampleDistance(double gsd_m, double lat, int tile_size) {
  const double zoom_at_one_metre = std::log2(MetersPerPixel(lat, 0, tile_size));
  return static_cast<int>(std::lround(zoom_at_one_metre - std::log2(gsd_m)));
}

LatLonBounds TileBounds(TileId t) {
  LatLon nw = PixelToLatLon({static_cast<double>(t.x), static_cast<double>(t.y)}, t.z, 1);
  LatLon se = PixelToLatLon({static_cast<double>(t.x + 1), static_cast<double>(t.y + 1)}, t.z, 1);
  return {nw.lon, se.lat, se.lon, nw.lat};
}

}  // namespace seamap
