#pragma once
// A box in global pixels of a zoom to the seabed: its lon/lat ring, centre,
// and east/north metres in the mission's local frame. Pixel coordinates are
// continuous, (0,0) the north-west corner of the north-west pixel, as in
// YOLO boxes and core/geo/web_mercator.h: no half-pixel shifts.
#include <array>

#include "core/geo/lat_lon.h"
#include "core/geo/local_frame.h"

namespace seamap {

struct PixelBox {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // global pixels at `zoom`, x east, y south
};

struct GeoBox {
  std::array<LatLon, 5> ring{};  // NW, SW, SE, NE, NW (counter-clockwise as [lon, lat], RFC 7946)
  LatLon centre;
  LocalXY centre_m;               // from the mission origin
  double west_m = 0, east_m = 0;  // metric box (edge midpoints)
  double south_m = 0, north_m = 0;
  double size_ew_m() const { return east_m - west_m; }
  double size_ns_m() const { return north_m - south_m; }
};

GeoBox ToGeo(const PixelBox& box, int zoom, int tile_size, const LocalFrame& frame);

}  // namespace seamap
