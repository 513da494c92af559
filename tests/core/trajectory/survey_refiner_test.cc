#include "core/trajectory/survey_refiner.h"

#include <gtest/gtest.h>

#include "core/util/process_stats.h"
#include "tests/testing/hostile_png.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

// The refiner reads its frames through the guarded read (core/image): a tiny
// PNG whose header claims 30000 x 30000 pixels is refused unread, with the
// reason, instead of being decoded into 900 MB.
TEST(RefineSurvey, FramesClaimingHugeImagesAreNotDecoded) {
  TempDir dir;
  CameraModel camera;
  camera.width = 640;
  camera.height = 480;
  camera.fx = camera.fy = 500;
  camera.cx = 319.5;
  camera.cy = 239.5;
  std::vector<FrameSpec> frames(2);
  for (int i = 0; i < 2; ++i) {
    frames[i].index = i;
    frames[i].image_path = (dir / ("claims" + std::to_string(i) + ".png")).string();
    testing::WriteBytes(frames[i].image_path, testing::ClaimingPng(30000, 30000));
    frames[i].time_s = i;
    frames[i].pose.east_m = i;
    frames[i].pose.altitude_m = 5;
  }
  RefineOptions options;
  options.threads = 1;
  RefineReport report;
  const int64_t rss_before = PeakRssBytes();
  const std::vector<RefinedFrame> refined = RefineSurvey(frames, camera, options, &report);
  ASSERT_EQ(refined.size(), 2u);
  for (const RefinedFrame& frame : refined) {
    EXPECT_EQ(frame.problem.rfind("image too large", 0), 0u) << frame.problem;
    EXPECT_TRUE(frame.nav_only);
  }
  EXPECT_EQ(report.frames_without_features, 2);
  EXPECT_LT(PeakRssBytes() - rss_before, int64_t{200} << 20) << "a refused image was decoded";
}

}  // namespace
}  // namespace seamap
