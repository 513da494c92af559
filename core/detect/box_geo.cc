#include "core/detect/box_geo.h"

#include "core/geo/web_mercator.h"

namespace seamap {

GeoBox ToGeo(const PixelBox& b, int zoom, int tile_size, const LocalFrame& frame) {
  const auto ll = [&](double x, double y) { return PixelToLatLon({x, y}, zoom, tile_size); };
  GeoBox g;
  g.ring = {ll(b.x0, b.y0), ll(b.x0, b.y1), ll(b.x1, b.y1), ll(b.x1, b.y0), ll(b.x0, b.y0)};
  const double cx = (b.x0 + b.x1) / 2, cy = (b.y0 + b.y1) / 2;
  g.centre = ll(cx, cy);
  g.centre_m = frame.FromLatLon(g.centre);
  g.west_m = frame.FromLatLon(ll(b.x0, cy)).east;
  g.east_m = frame.FromLatLon(ll(b.x1, cy)).east;
  g.north_m = frame.FromLatLon(ll(cx, b.y0)).north;
  g.south_m = frame.FromLatLon(ll(cx, b.y1)).north;
  return g;
}

}  // namespace seamap
