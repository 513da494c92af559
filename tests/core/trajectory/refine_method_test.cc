#include "core/trajectory/refine_method.h"

#include <gtest/gtest.h>

#include <cmath>

namespace seamap {
namespace {

// 300 frames at 5 frames/s, 2 m above a seabed `seabed_up(t)` metres up, the
// vehicle holding its depth (or, with follow, its altitude).
std::vector<FrameSpec> Track(double (*seabed_up)(double), bool follow = false) {
  std::vector<FrameSpec> frames(300);
  for (size_t i = 0; i < frames.size(); ++i) {
    const double t = i / 5.0;
    frames[i].time_s = t;
    frames[i].pose.altitude_m = follow ? 2 : 2 + (seabed_up(0) - seabed_up(t));
    frames[i].pose.depth_m = -seabed_up(t) - frames[i].pose.altitude_m;
  }
  return frames;
}

std::vector<double> Times(const std::vector<FrameSpec>& frames) {
  std::vector<double> t;
  for (const auto& f : frames) t.push_back(*f.time_s);
  return t;
}

TEST(RefineMethod, AFlatSeabedKeepsThePlanarGraph) {
  const auto frames = Track([](double) { return -30.0; });
  const ReliefChoice c = ChooseRefineMethod(frames, Times(frames));
  EXPECT_EQ(c.method, RefineMethod::kPlanar);
  ASSERT_TRUE(c.relief_rms_m.has_value());
  EXPECT_LT(*c.relief_rms_m, 1e-9);
  EXPECT_DOUBLE_EQ(c.altitude_m, 2);
}

TEST(RefineMethod, AGentleSlopeOfTheSiteIsNotRelief) {
  // 1 m over the 60 s survey (30 m at 0.5 m/s): locally a plane.
  const auto frames = Track([](double t) { return -30 + t / 60; });
  EXPECT_EQ(ChooseRefineMethod(frames, Times(frames)).method, RefineMethod::kPlanar);
}

TEST(RefineMethod, ReliefUnderTheTrackPicksTheBundle) {
  // Bumps of 0.05 m amplitude every ~2 m at 0.5 m/s: 35 mm rms, 1.8 % of the altitude.
  const auto frames = Track([](double t) { return -30 + 0.05 * std::sin(1.6 * t); });
  const ReliefChoice c = ChooseRefineMethod(frames, Times(frames));
  EXPECT_EQ(c.method, RefineMethod::kBundle);
  EXPECT_NEAR(*c.relief_rms_m, 0.035, 0.01);
  // The same seabed followed at constant altitude shows in the depth instead.
  const auto following = Track([](double t) { return -30 + 0.05 * std::sin(1.6 * t); }, true);
  EXPECT_EQ(ChooseRefineMethod(following, Times(following)).method, RefineMethod::kBundle);
}

TEST(RefineMethod, ASurveyTooLongForOneBundleIsSolvedInWindowsAndSaysSo) {
  const auto frames = Track([](double t) { return -30 + 0.05 * std::sin(1.6 * t); });
  ReliefChoiceOptions options;
  options.max_bundle_frames = 299;  // the 300 frames are one too many
  options.bundle_window_frames = 120;
  const ReliefChoice c = ChooseRefineMethod(frames, Times(frames), options);
  EXPECT_EQ(c.method, RefineMethod::kBundle);
  EXPECT_EQ(c.bundle_window_frames, 120);
  EXPECT_NE(c.note.find("300 frames, more than 299: solved in windows of 120"), std::string::npos) << c.note;
  options.max_bundle_frames = 300;
  const ReliefChoice one = ChooseRefineMethod(frames, Times(frames), options);
  EXPECT_EQ(one.method, RefineMethod::kBundle);
  EXPECT_EQ(one.bundle_window_frames, 0);  // one bundle
  EXPECT_TRUE(one.note.empty());
  // By default: one bundle up to 450 frames, windows of 300 past that.
  EXPECT_EQ(ChooseRefineMethod(frames, Times(frames)).bundle_window_frames, 0);
  EXPECT_EQ(ReliefChoiceOptions().max_bundle_frames, 450);
  EXPECT_EQ(ReliefChoiceOptions().bundle_window_frames, 300);
}

TEST(RefineMethod, WithoutAltitudesNothingSaysTheSeabedIsRough) {
  auto frames = Track([](double t) { return -30 + 0.05 * std::sin(1.6 * t); });
  for (auto& f : frames) f.pose.altitude_m = 0;
  const ReliefChoice c = ChooseRefineMethod(frames, Times(frames));
  EXPECT_EQ(c.method, RefineMethod::kPlanar);
  EXPECT_FALSE(c.relief_rms_m.has_value());
}

}  // namespace
}  // namespace seamap
