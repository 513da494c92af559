#include "core/controllers/seabed_surface.h"

#include <cmath>
#include <limits>
#include <memory>

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace seamap {
namespace {

// Ten frames along north at 33 m depth, 2 m altitude: the seabed at -35 m.
std::vector<FrameSpec> Frames() {
  std::vector<FrameSpec> frames(10);
  for (int i = 0; i < 10; ++i) {
    frames[i].index = i;
    frames[i].pose.north_m = 0.1 * i;
    frames[i].pose.depth_m = 33;
    frames[i].pose.altitude_m = 2;
  }
  return frames;
}

SeabedSurface Flat(double up_m) {
  auto g = std::make_shared<HeightGrid>();
  g->cell_m = 0.05;
  g->east0_m = -3;
  g->north0_m = 4;
  g->height_m = cv::Mat1f(140, 120, static_cast<float>(up_m));
  SeabedSurface s;
  s.grid = g;
  s.source = "file dem.tif";
  s.path = "dem.tif";
  return s;
}

TEST(SeabedSurface, AModelOnTheNavigationsSeabedIsTaken) {
  const CameraModel camera = CameraFromFocalLength(8, 12.9, 320, 240);
  SeabedSurface s = Flat(-35.2);
  CheckAgainstNavigation(camera, Frames(), "--terrain-file", &s);
  EXPECT_NEAR(s.datum_offset_m, -0.2, 1e-5);
  EXPECT_NEAR(s.hole_share, 0, 1e-9);
  EXPECT_NE(s.Summary().find("-0.20 m"), std::string::npos) << s.Summary();
}

TEST(SeabedSurface, HolesAreCounted) {
  const CameraModel camera = CameraFromFocalLength(8, 12.9, 320, 240);
  SeabedSurface s = Flat(-35);
  auto g = std::const_pointer_cast<HeightGrid>(s.grid);
  g->height_m(cv::Rect(0, 0, 60, 140)) = std::numeric_limits<float>::quiet_NaN();  // the western half
  CheckAgainstNavigation(camera, Frames(), "--terrain-file", &s);
  EXPECT_GT(s.hole_share, 0.2);
  EXPECT_LT(s.hole_share, 0.6);
}

TEST(SeabedSurface, AModelOnAnotherDatumIsRefusedNamingTheFile) {
  const CameraModel camera = CameraFromFocalLength(8, 12.9, 320, 240);
  SeabedSurface s = Flat(0.0);  // heights relative to the seabed, not the sea surface
  try {
    CheckAgainstNavigation(camera, Frames(), "--terrain-file", &s);
    FAIL() << "accepted a model 35 m off";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dem.tif"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("35.00 m above"), std::string::npos) << e.what();
  }
  SeabedSurface elsewhere = Flat(-35);
  std::const_pointer_cast<HeightGrid>(elsewhere.grid)->east0_m = 500;  // another site
  EXPECT_THROW(CheckAgainstNavigation(camera, Frames(), "--terrain-file", &elsewhere), InputError);
}

}  // namespace
}  // namespace seamap
