// Reading stereo-points' CSV into a build's local frame (build --terrain-points).
#include "core/controllers/stereo_seabed.h"

#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

std::string Write(const testing::TempDir& dir, const std::string& text) {
  const std::string path = (dir / "points.csv").string();
  std::ofstream(path) << text;
  return path;
}

std::string ErrorOf(const std::string& path, const LocalFrame& frame) {
  try {
    ReadStereoSeabedPoints(path, frame);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(StereoSeabed, PointsAreReadIntoTheBuildsFrame) {
  testing::TempDir dir;
  const LocalFrame frame({43.1, 131.9});
  const LatLon at = frame.ToLatLon({3.25, -1.5});
  const std::string path =
      Write(dir, "pair,lat,lon,up_m,sigma_up_m\n" + cv::format("p1,%.9f,%.9f,-30.125,0.004\n", at.lat, at.lon) +
                     cv::format("p1,%.9f,%.9f,-29.5,0.01\n", at.lat, at.lon));
  const SeabedPoints points = ReadStereoSeabedPoints(path, frame);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_NEAR(points[0].east_north_up_m.x(), 3.25, 1e-3);
  EXPECT_NEAR(points[0].east_north_up_m.y(), -1.5, 1e-3);
  EXPECT_DOUBLE_EQ(points[0].east_north_up_m.z(), -30.125);
  EXPECT_DOUBLE_EQ(points[0].sigma_up_m, 0.004);
  EXPECT_EQ(points[1].views, 2);
  // Another origin: the same place, other local metres.
  const LocalFrame other({43.1001, 131.9});
  EXPECT_NEAR(ReadStereoSeabedPoints(path, other)[0].east_north_up_m.y(), -1.5 - 11.1, 0.1);
}

TEST(StereoSeabed, BadRowsAreNamedByFileLineAndColumn) {
  testing::TempDir dir;
  const LocalFrame frame({43.1, 131.9});
  const std::string header = "pair,lat,lon,up_m,sigma_up_m\n";
  std::string e = ErrorOf(Write(dir, header + "p,43.1,131.9,-30,zero\n"), frame);
  EXPECT_NE(e.find("points.csv:2"), std::string::npos) << e;
  EXPECT_NE(e.find("sigma_up_m"), std::string::npos) << e;
  e = ErrorOf(Write(dir, header + "p,43.1,131.9,-30,0\n"), frame);
  EXPECT_NE(e.find("sigma_up_m"), std::string::npos) << e;
  e = ErrorOf(Write(dir, header + "p,143.1,131.9,-30,0.01\n"), frame);
  EXPECT_NE(e.find("lat"), std::string::npos) << e;
  e = ErrorOf(Write(dir, "pair,lat,lon,height\np,43.1,131.9,-30\n"), frame);
  EXPECT_NE(e.find("up_m"), std::string::npos) << e;
  EXPECT_THROW(ReadStereoSeabedPoints(Write(dir, header + "p,43.1,131.9,-30,0.01\np,43.1,131.9,-30,0.01\n"), frame, 1),
               InputError);
}

}  // namespace
}  // namespace seamap
