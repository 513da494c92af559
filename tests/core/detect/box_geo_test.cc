#include "core/detect/box_geo.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

TEST(BoxGeo, CornersAreTheExactPixelCornersWithoutHalfPixelShifts) {
  const LocalFrame frame({43.1, 131.9});
  const int z = 23, t = 256;
  const GlobalPixel p = LatLonToPixel({43.1, 131.9}, z, t);
  const double x = std::floor(p.x), y = std::floor(p.y);
  const GeoBox g = ToGeo({x, y, x + 100, y + 50}, z, t, frame);
  const LatLon nw = PixelToLatLon({x, y}, z, t), se = PixelToLatLon({x + 100, y + 50}, z, t);
  EXPECT_DOUBLE_EQ(g.ring[0].lat, nw.lat);
  EXPECT_DOUBLE_EQ(g.ring[0].lon, nw.lon);
  EXPECT_DOUBLE_EQ(g.ring[2].lat, se.lat);
  EXPECT_DOUBLE_EQ(g.ring[2].lon, se.lon);
  EXPECT_EQ(g.ring[4].lat, g.ring[0].lat);
  // Centre: the box's middle pixel coordinate, not shifted by half a pixel.
  const LatLon c = PixelToLatLon({x + 50, y + 25}, z, t);
  EXPECT_DOUBLE_EQ(g.centre.lat, c.lat);
  EXPECT_DOUBLE_EQ(g.centre.lon, c.lon);
}

TEST(BoxGeo, RingIsCounterClockwise) {
  const LocalFrame frame({-33.0, 151.0});
  const GlobalPixel p = LatLonToPixel({-33.0, 151.0}, 22, 256);
  const GeoBox g = ToGeo({p.x, p.y, p.x + 40, p.y + 30}, 22, 256, frame);
  double area2 = 0;  // shoelace on [lon, lat]: positive = counter-clockwise
  for (int i = 0; i < 4; ++i) area2 += g.ring[i].lon * g.ring[i + 1].lat - g.ring[i + 1].lon * g.ring[i].lat;
  EXPECT_GT(area2, 0);
  EXPECT_GT(g.ring[0].lat, g.ring[1].lat);  // NW then SW
}

// Web Mercator is spherical and the local frame ellipsoidal: north-south
// they differ by up to 0.67 % at the equator, under 0.3 % from 40 deg on.
TEST(BoxGeo, SizesAgreeWithMetresPerPixelWithin0_3Percent) {
  for (double lat : {43.1, -50.0, 60.0})
    for (int z : {18, 21, 25}) {
      const LocalFrame frame({lat, 10.0});
      const GlobalPixel p = LatLonToPixel({lat, 10.0}, z, 256);
      const GeoBox g = ToGeo({p.x - 60, p.y - 40, p.x + 60, p.y + 40}, z, 256, frame);
      const double gz = MetersPerPixel(lat, z, 256);
      EXPECT_NEAR(g.size_ew_m() / (120 * gz), 1, 0.003) << lat << " " << z;
      EXPECT_NEAR(g.size_ns_m() / (80 * gz), 1, 0.003) << lat << " " << z;
      EXPECT_NEAR(g.centre_m.east, 0, 1e-4);
      EXPECT_NEAR(g.centre_m.north, 0, 1e-4);
    }
}

}  // namespace
}  // namespace seamap
