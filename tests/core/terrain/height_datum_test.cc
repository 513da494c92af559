#include "core/terrain/height_datum.h"

#include <cmath>

#include <gtest/gtest.h>

namespace seamap {
namespace {

HeightGrid Grid(bool depth_datum) {
  HeightGrid g;
  g.height_m = cv::Mat1f(2, 3);
  g.height_m << -10, -11, -12, NAN, -13, -14;  // mean of the five: -12
  g.sigma_m = cv::Mat1f(2, 3, 0.02f);
  g.has_depth_datum = depth_datum;
  return g;
}

TEST(HeightDatum, SeaSurfaceKeepsTheStoredHeights) {
  const HeightDatum d = UserDatum(Grid(true));
  EXPECT_EQ(d.name, "sea_surface");
  EXPECT_EQ(d.offset_m, 0);
}

TEST(HeightDatum, WithoutDepthHeightsAreRelativeToTheMeanSeabedIgnoringHoles) {
  const HeightDatum d = UserDatum(Grid(false));
  EXPECT_EQ(d.name, "mean_seabed");
  EXPECT_NEAR(d.offset_m, 12, 1e-9);
}

TEST(HeightDatum, AGridOfHolesHasNoOffset) {
  HeightGrid g = Grid(false);
  g.height_m.setTo(NAN);
  EXPECT_EQ(UserDatum(g).offset_m, 0);
}

}  // namespace
}  // namespace seamap
