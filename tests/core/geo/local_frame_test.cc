#include "core/geo/local_frame.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/error.h"

namespace seamap {
namespace {

// Geodesic distance on the WGS84 ellipsoid for short baselines, from the
// meridian (M) and prime vertical (N) radii of curvature: independent of PROJ.
void EllipsoidOffset(LatLon a, LatLon b, double* east, double* north) {
  const double A = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  const double phi = (a.lat + b.lat) / 2 * M_PI / 180;
  const double w = 1 - e2 * std::sin(phi) * std::sin(phi);
  const double M = A * (1 - e2) / std::pow(w, 1.5), N = A / std::sqrt(w);
  *north = (b.lat - a.lat) * M_PI / 180 * M;
  *east = (b.lon - a.lon) * M_PI / 180 * N * std::cos(phi);
}

TEST(LocalFrame, OriginMapsToZero) {
  LocalFrame frame({43.1, 131.9});
  LocalXY xy = frame.FromLatLon({43.1, 131.9});
  EXPECT_NEAR(xy.east, 0, 1e-9);
  EXPECT_NEAR(xy.north, 0, 1e-9);
}

TEST(LocalFrame, RoundTripIsExact) {
  LocalFrame frame({-33.9, 18.4});
  for (double e : {-500.0, 0.0, 12.345, 800.0})
    for (double n : {-300.0, 0.5, 999.0}) {
      LocalXY back = frame.FromLatLon(frame.ToLatLon({e, n}));
      EXPECT_NEAR(back.east, e, 1e-7);
      EXPECT_NEAR(back.north, n, 1e-7);
    }
}

TEST(LocalFrame, MetresAreEllipsoidalNotSpherical) {
  // 100 m north and east at 43.1 N: the ellipsoid radii differ from the
  // sphere by about 0.2-0.7 %, i.e. 20-70 cm over 100 m; we must agree with
  // the ellipsoid to the millimetre.
  LocalFrame frame({43.1, 131.9});
  LatLon ll = frame.ToLatLon({100.0, 100.0});
  double east, north;
  EllipsoidOffset({43.1, 131.9}, ll, &east, &north);
  EXPECT_NEAR(east, 100.0, 2e-3);
  EXPECT_NEAR(north, 100.0, 2e-3);
  // And the spherical shortcut would be off by more than that.
  const double sphere_north = (ll.lat - 43.1) * M_PI / 180 * 6371008.8;
  EXPECT_GT(std::fabs(sphere_north - 100.0), 0.05);
}

TEST(LocalFrame, CopiesAreIndependent) {
  LocalFrame a({10, 20});
  LocalFrame b = a;
  EXPECT_DOUBLE_EQ(b.origin().lat, 10);
  LatLon la = a.ToLatLon({5, 5}), lb = b.ToLatLon({5, 5});
  EXPECT_DOUBLE_EQ(la.lat, lb.lat);
  EXPECT_DOUBLE_EQ(la.lon, lb.lon);
}

TEST(LocalFrame, RejectsOriginOutOfRange) {
  try {
    LocalFrame frame({91, 0});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "--origin");
    EXPECT_NE(std::string(e.what()).find("[-90, 90]"), std::string::npos);
  }
  EXPECT_THROW(LocalFrame({NAN, 0}), InputError);
}

TEST(Utm, KnownPoint) {
  // Central meridian of zone 52 is 129 E; easting 500000 lies on it.
  LatLon ll = UtmToLatLon(500000, 4000000, 52, true);
  EXPECT_NEAR(ll.lon, 129.0, 1e-9);
  // On the central meridian, northing = 0.9996 * meridian arc from the equator;
  // integrate the meridian radius of curvature independently of PROJ.
  const double A = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  const int steps = 2000;
  const double phi_end = ll.lat * M_PI / 180;
  double arc = 0;
  for (int i = 0; i < steps; ++i) {
    const double phi = (i + 0.5) * phi_end / steps;
    arc += A * (1 - e2) / std::pow(1 - e2 * std::sin(phi) * std::sin(phi), 1.5) * phi_end / steps;
  }
  EXPECT_NEAR(0.9996 * arc, 4000000.0, 0.05);
  LatLon south = UtmToLatLon(500000, 10000000 - 4000000, 52, false);
  EXPECT_NEAR(south.lat, -ll.lat, 1e-9);
  EXPECT_THROW(UtmToLatLon(500000, 0, 61, true), InputError);
}

}  // namespace
}  // namespace seamap
