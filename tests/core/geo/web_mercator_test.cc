#include "core/geo/web_mercator.h"

#include <gtest/gtest.h>

#include <cmath>

namespace seamap {
namespace {

TEST(WebMercator, KnownTile) {
  // The tile holding lat 43.1, lon 131.9 at z=10 (checked against the OSM slippy-map formula).
  GlobalPixel p = LatLonToPixel({43.1, 131.9}, 10, 256);
  EXPECT_EQ(static_cast<int>(p.x / 256), 887);
  EXPECT_EQ(static_cast<int>(p.y / 256), 375);
}

TEST(WebMercator, CornersOfTheWorld) {
  GlobalPixel nw = LatLonToPixel({kWebMercatorMaxLat, -180}, 3, 256);
  EXPECT_NEAR(nw.x, 0, 1e-9);
  EXPECT_NEAR(nw.y, 0, 1e-6);
  GlobalPixel c = LatLonToPixel({0, 0}, 3, 256);
  EXPECT_NEAR(c.x, 1024, 1e-9);
  EXPECT_NEAR(c.y, 1024, 1e-9);
}

TEST(WebMercator, RoundTripAtHighZoom) {
  for (int z : {0, 12, 26}) {
    LatLon ll{-43.123456789, 131.987654321};
    LatLon back = PixelToLatLon(LatLonToPixel(ll, z, 256), z, 256);
    EXPECT_NEAR(back.lat, ll.lat, 1e-10);
    EXPECT_NEAR(back.lon, ll.lon, 1e-10);
  }
}

TEST(WebMercator, MetersPerPixel) {
  EXPECT_NEAR(MetersPerPixel(0, 0, 256), 156543.03392804097, 1e-6);
  EXPECT_NEAR(MetersPerPixel(60, 1, 256), 156543.03392804097 / 4, 1e-6);
  EXPECT_NEAR(MetersPerPixel(0, 0, 512), 156543.03392804097 / 2, 1e-6);
}

TEST(WebMercator, ZoomForGsd) {
  // 2.9 mm at 43.1 N: z25 is 3.4 mm, z26 1.7 mm; log-nearest is 25.
  EXPECT_EQ(ZoomForGroundSampleDistance(0.0029, 43.1, 256), 25);
  EXPECT_EQ(ZoomForGroundSampleDistance(MetersPerPixel(10, 18, 256), 10, 256), 18);
}

TEST(WebMercator, TileIdHelpers) {
  TileId t{5, 10, 3};
  EXPECT_EQ(t.TmsRow(), 28);
  EXPECT_EQ(t.Parent(), (TileId{4, 5, 1}));
  LatLonBounds b = TileBounds({1, 0, 0});
  EXPECT_NEAR(b.west, -180, 1e-9);
  EXPECT_NEAR(b.east, 0, 1e-9);
  EXPECT_NEAR(b.south, 0, 1e-9);
  EXPECT_NEAR(b.north, kWebMercatorMaxLat, 1e-9);
}

}  // namespace
}  // namespace seamap
