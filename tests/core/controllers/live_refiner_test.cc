// Refinement as frames arrive (replay --refine-nav) on a small simulated
// survey whose navigation drifts: the incremental refiner ends where
// RefineSurvey's planar graph ends, and the live worker hands back the
// frames it moved as passes cross.
#include "core/controllers/live_refiner.h"

#include <atomic>
#include <cmath>
#include <thread>

#include <gtest/gtest.h>

#include "core/nav/frame_list.h"
#include "core/nav/nav_reader.h"
#include "core/sim/survey_simulator.h"
#include "core/trajectory/incremental_refiner.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

// 60 frames over three 3 m lines 0.9 m apart, drifting 1 m/min; features at
// a working size of 400 px (a quarter of the default's work).
struct Survey {
  testing::TempDir dir;
  std::vector<FrameSpec> frames;
  RefineOptions refine;
  Survey() {
    SimulationOptions o;
    o.out_dir = (dir / "s").string();
    o.seed = 4;
    o.image_format = "jpg";
    o.trajectory.frames = 60;
    o.line_length_m = 3;
    o.line_spacing_m = 0.9;
    o.nav_errors.position_sigma_m = 0.005;
    o.nav_errors.heading_sigma_deg = 0.5;
    o.nav_errors.drift_m_per_min = 1;
    SimulateSurvey(o);
    NavReadOptions nav;
    nav.origin = o.origin;
    frames = MatchFrames(ReadNavigation(o.out_dir + "/nav.csv", nav), o.out_dir + "/photo", std::nullopt).frames;
    refine.method = RefineMethod::kPlanar;
    refine.nav_noise_m = 0.005;
    refine.nav_drift_m_per_min = 1;
    refine.features.max_side_px = 400;
    refine.heading_noise_deg = 0.5;
    refine.threads = 2;
  }
};

const Survey& TheSurvey() {
  static const Survey* survey = new Survey();
  return *survey;
}

TEST(IncrementalRefiner, EndsWhereTheWholeSurveysPlanarGraphEnds) {
  const Survey& s = TheSurvey();
  ASSERT_EQ(s.frames.size(), 60u);
  const CameraModel camera = DefaultSimCamera();
  RefineReport report;
  const std::vector<RefinedFrame> whole = RefineSurvey(s.frames, camera, s.refine, &report);

  IncrementalRefiner incremental(camera, s.refine);
  int cross = 0, cross_before_second_line = 0;
  for (size_t begin = 0; begin < s.frames.size(); begin += 7) {
    const std::vector<FrameSpec> batch(s.frames.begin() + begin,
                                       s.frames.begin() + std::min(s.frames.size(), begin + 7));
    cross += incremental.Add(batch);
    if (begin + 7 <= 14) cross_before_second_line = cross;
  }
  EXPECT_EQ(cross_before_second_line, 0);  // the first line crosses nothing
  EXPECT_GE(cross, 5);
  const IncrementalSolution solved = incremental.Solve();
  ASSERT_EQ(solved.poses.size(), s.frames.size());
  EXPECT_EQ(solved.registered_cross, report.registered_cross);
  EXPECT_EQ(solved.registered_along, report.registered_along);
  double worst_m = 0, moved_m = 0;
  for (size_t i = 0; i < whole.size(); ++i) {
    worst_m = std::max(worst_m, std::hypot(solved.poses[i].east_m - whole[i].pose.east_m,
                                           solved.poses[i].north_m - whole[i].pose.north_m));
    moved_m = std::max(moved_m, std::hypot(s.frames[i].pose.east_m - whole[i].pose.east_m,
                                           s.frames[i].pose.north_m - whole[i].pose.north_m));
  }
  EXPECT_GT(moved_m, 0.02);  // the refinement did move the frames
  EXPECT_LT(worst_m, 1e-4);  // and both ways to the same place
}

TEST(LiveRefiner, HandsBackTheFramesThatMovedAsPassesCross) {
  const Survey& s = TheSurvey();
  LiveRefinerOptions options;
  options.refine = s.refine;
  options.base_pixel_m = 0.002;
  options.min_frames_between_solves = 5;
  std::atomic<int> solves{0}, handed_back{0};
  std::atomic<bool> bad{false};
  std::atomic<double> residual_before{0}, residual_after{0};
  {
    LiveRefiner live(DefaultSimCamera(), options, [&](const LiveCorrection& c) {
      ++solves;
      handed_back += static_cast<int>(c.moved.size());
      bad = bad || c.moved.size() != c.before.size() || c.placed.size() > s.frames.size() || c.solve != solves;
      for (int i : c.moved) bad = bad || !c.placed[i].nav_pose;  // a moved frame keeps its navigation
      // The seams close: the pairs' disagreement falls from the navigation's to a few mm.
      residual_before = c.solution.residual_before_mm;
      residual_after = c.solution.residual_after_mm;
    });
    for (const FrameSpec& f : s.frames) {
      live.Add(f, f.pose);
      std::this_thread::sleep_for(std::chrono::milliseconds(40));  // a camera's pace, faster
    }
    for (int wait = 0; wait < 200 && live.Lag().frames_behind > 0; ++wait)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const LiveRefinerLag lag = live.Lag();
    EXPECT_GE(lag.cross_pairs, 5);
    EXPECT_EQ(lag.solves, solves.load());
    live.Stop();
  }
  EXPECT_FALSE(bad);
  EXPECT_GE(solves.load(), 1);
  EXPECT_GT(handed_back.load(), 10);
  // The last solve's disagreement before depends on how many frames the
  // worker had taken by then (the machine's pace): 19.7-30 mm measured.
  EXPECT_GT(residual_before.load(), 10);
  EXPECT_GT(residual_before.load(), 4 * residual_after.load());
  EXPECT_LT(residual_after.load(), 5);
}

TEST(LiveRefiner, RefusesOptionsThatDoNotFit) {
  LiveRefinerOptions options;
  options.base_pixel_m = 0;
  EXPECT_THROW(LiveRefiner refiner(DefaultSimCamera(), options, nullptr), InputError);
}

}  // namespace
}  // namespace seamap
