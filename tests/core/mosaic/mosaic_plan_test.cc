#include "core/mosaic/mosaic_plan.h"

#include <gtest/gtest.h>

#include "core/mosaic/frame_pipeline.h"
#include "core/mosaic/seabed_projection.h"
#include "core/util/error.h"

namespace seamap {
namespace {

std::vector<FrameSpec> Frames(double altitude_m) {
  std::vector<FrameSpec> frames(10);
  for (size_t i = 0; i < frames.size(); ++i) {
    frames[i].pose.east_m = 0.2 * static_cast<double>(i);
    frames[i].pose.altitude_m = altitude_m;
  }
  return frames;
}

// --base-zoom 30 on a 2 m survey: one frame would cover millions of tiles.
TEST(MosaicPlan, ABaseZoomWhoseTilesCannotFitIsRefusedWithTheMemoryItNeeds) {
  const CameraModel camera = CameraFromFocalLength(8, 12.9, 696, 520);
  const LocalFrame frame({43.1, 131.9});
  MapSettings map;
  map.base_zoom = 30;
  MosaicPlan plan = PlanMosaic(map, camera, frame, Frames(2), 1);
  ASSERT_EQ(plan.base_zoom, 30);
  try {
    CheckPlanFitsMemory(plan, camera, 256, 512, "");
    FAIL() << "zoom 30 accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "base_zoom");
    const std::string what = e.what();
    EXPECT_NE(what.find("base zoom 30"), std::string::npos) << what;
    EXPECT_NE(what.find("memory_cap_mb 512"), std::string::npos) << what;
    EXPECT_NE(what.find(" MB of tiles"), std::string::npos) << what;
    // The zoom it proposes fits, the one above it does not.
    const size_t at = what.find("use --base-zoom ");
    ASSERT_NE(at, std::string::npos) << what;
    const int proposed = std::stoi(what.substr(at + 16));
    plan.base_zoom = proposed;
    EXPECT_NO_THROW(CheckPlanFitsMemory(plan, camera, 256, 512, ""));
    plan.base_zoom = proposed + 1;
    EXPECT_THROW(CheckPlanFitsMemory(plan, camera, 256, 512, ""), InputError);
  }
  // A 12 MP colour camera at its own zoom fits the default cap, however turned.
  const CameraModel big = CameraFromFocalLength(8, 3.45, 4096, 3000);
  map.base_zoom.reset();
  const MosaicPlan colour = PlanMosaic(map, big, frame, Frames(2), 3);
  EXPECT_NO_THROW(CheckPlanFitsMemory(colour, big, 256, 512, ""));
  const SeabedProjection projection(big, frame, colour.base_zoom, 256);
  VehiclePose turned;
  turned.altitude_m = 2;
  turned.heading_deg = 45;
  EXPECT_FALSE(TooLargeToPaint(projection, turned, 3, FramePaintLimitBytes(colour, big, 256, 512)));
  // The zoom chosen from the ground sample distance fits easily.
  map.base_zoom.reset();
  EXPECT_NO_THROW(CheckPlanFitsMemory(PlanMosaic(map, camera, frame, Frames(2), 3), camera, 256, 512, ""));
}

TEST(MosaicPlan, FramePaintBytesCountsPixelsAndTheTilesUnderThem) {
  // One tile's box: its pixels (value + mask) and up to four tiles of float sums and weights.
  EXPECT_DOUBLE_EQ(FramePaintBytes(256, 256, 256, 1), 256.0 * 256 * 2 + 9 * 256.0 * 256 * 8);
  EXPECT_GT(FramePaintBytes(1e9, 1e9, 256, 3), 1e18);  // no overflow
}

// A frame far above the survey (altitude 900 m where the map is made for
// 2 m) covers thousands of tiles at the base zoom: refused, naming altitude.
TEST(MosaicPlan, AFrameTooHighForTheMapIsRefused) {
  const CameraModel camera = CameraFromFocalLength(8, 12.9, 696, 520);
  const LocalFrame frame({43.1, 131.9});
  const MosaicPlan plan = PlanMosaic(MapSettings{}, camera, frame, Frames(2), 1);
  const SeabedProjection projection(camera, frame, plan.base_zoom, 256);
  const double limit = FramePaintLimitBytes(plan, camera, 256, 512);
  EXPECT_DOUBLE_EQ(limit, 512.0 * (1 << 20));  // a small frame: the cap
  VehiclePose pose;
  pose.altitude_m = 2;
  EXPECT_FALSE(TooLargeToPaint(projection, pose, 1, limit));
  pose.altitude_m = 6;  // a dip in the seabed, the frame turned: still painted
  pose.heading_deg = 45;
  EXPECT_FALSE(TooLargeToPaint(projection, pose, 1, limit));
  pose.altitude_m = 900;
  const auto why = TooLargeToPaint(projection, pose, 1, limit);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("frame too large for the map: at altitude 900 m"), std::string::npos) << *why;
  EXPECT_NE(why->find("memory_cap_mb"), std::string::npos) << *why;
}

}  // namespace
}  // namespace seamap
