#include "core/geo/utm.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace seamap {
namespace {

TEST(UtmZoneFor, StandardZonesAndHemisphere) {
  EXPECT_EQ(UtmZoneFor({51.05, 13.74}).Name(), "33N");    // Dresden
  EXPECT_EQ(UtmZoneFor({-33.86, 151.21}).Name(), "56S");  // Sydney
  EXPECT_EQ(UtmZoneFor({-33.86, 151.21}).Epsg(), 32756);
  EXPECT_EQ(UtmZoneFor({43.1, 131.9}).Epsg(), 32652);
  EXPECT_EQ(UtmZoneFor({0.0, -180.0}).zone, 1);
  EXPECT_EQ(UtmZoneFor({0.0, 180.0}).zone, 60);
}

TEST(UtmZoneFor, NorwayAndSvalbardExceptions) {
  EXPECT_EQ(UtmZoneFor({60.39, 5.32}).zone, 32);   // Bergen: 31 by the rule, 32V in fact
  EXPECT_EQ(UtmZoneFor({55.9, 5.32}).zone, 31);    // south of band V
  EXPECT_EQ(UtmZoneFor({78.22, 15.65}).zone, 33);  // Longyearbyen
  EXPECT_EQ(UtmZoneFor({78.0, 8.0}).zone, 31);
  EXPECT_EQ(UtmZoneFor({78.0, 25.0}).zone, 35);
  EXPECT_EQ(UtmZoneFor({78.0, 40.0}).zone, 37);
}

TEST(UtmProjection, PublishedReferencePoint) {
  // The central meridian of zone 33 at the equator: easting 500 km exactly,
  // and 1 degree north on it: northing 110,574.389 m (WGS84 meridian arc x 0.9996).
  UtmProjection utm({33, true});
  const UtmXY equator = utm.Forward({0, 15});
  EXPECT_NEAR(equator.easting, 500000.0, 1e-6);
  EXPECT_NEAR(equator.northing, 0.0, 1e-6);
  const UtmXY one_degree = utm.Forward({1, 15});
  EXPECT_NEAR(one_degree.easting, 500000.0, 1e-6);
  EXPECT_NEAR(one_degree.northing, 110574.389 * 0.9996, 0.01);
  UtmProjection south({33, false});
  EXPECT_NEAR(south.Forward({-1, 15}).northing, 1e7 - 110574.389 * 0.9996, 0.01);
}

TEST(UtmProjection, RoundTripWithinAMillimetre) {
  for (const LatLon p : {LatLon{51.05, 13.74}, LatLon{-33.86, 151.21}, LatLon{78.22, 15.65}, LatLon{60.39, 5.32}}) {
    UtmProjection utm(UtmZoneFor(p));
    const LatLon back = utm.Inverse(utm.Forward(p));
    EXPECT_NEAR(back.lat, p.lat, 1e-8);  // 1e-8 degrees ~ 1 mm
    EXPECT_NEAR(back.lon, p.lon, 1e-8);
  }
}

TEST(UtmProjection, RefusesABadZone) {
  EXPECT_THROW(UtmProjection({0, true}), InputError);
  EXPECT_THROW(UtmProjection({61, true}), InputError);
}

}  // namespace
}  // namespace seamap
