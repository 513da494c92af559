// The live refiner's bounded features (issue 30): past the bound, the
// features of frames already paired and far from the vehicle are freed and
// extracted again when a later pass comes back to them; the registrations,
// and so the solution, are those kept with every frame's features.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "core/nav/frame_list.h"
#include "core/nav/nav_reader.h"
#include "core/sim/survey_simulator.h"
#include "core/trajectory/incremental_refiner.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

// 60 frames over three 3 m lines 0.9 m apart, drifting 1 m/min; features at
// a working size of 400 px.
struct Survey {
  testing::TempDir dir;
  std::vector<FrameSpec> frames;
  RefineOptions refine;
  Survey() {
    SimulationOptions o;
    o.out_dir = (dir / "s").string();
    o.seed = 6;
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

// Frames in batches of 5, as a worker takes them.
IncrementalSolution Refine(IncrementalRefiner* refiner, const std::vector<FrameSpec>& frames) {
  for (size_t begin = 0; begin < frames.size(); begin += 5)
    refiner->Add({frames.begin() + begin, frames.begin() + std::min(frames.size(), begin + 5)});
  return refiner->Solve();
}

TEST(IncrementalRefinerMemory, BoundedFeaturesGiveTheSameSolution) {
  const Survey s;
  ASSERT_EQ(s.frames.size(), 60u);
  const CameraModel camera = DefaultSimCamera();
  IncrementalRefiner unbounded(camera, s.refine);
  const IncrementalSolution all = Refine(&unbounded, s.frames);
  EXPECT_EQ(unbounded.features_freed(), 0);
  EXPECT_EQ(unbounded.feature_bytes(), unbounded.peak_feature_bytes());  // every frame's kept

  // A quarter of every frame's features; the last 10 frames always kept.
  FeatureBound bound;
  bound.max_bytes = unbounded.peak_feature_bytes() / 4;
  bound.recent_frames = 10;
  IncrementalRefiner bounded(camera, s.refine, bound);
  const IncrementalSolution some = Refine(&bounded, s.frames);
  std::printf("features: unbounded %.1f MB; bounded to %.1f MB: peak %.1f MB, %d frames freed, %d extracted again\n",
              unbounded.peak_feature_bytes() / 1e6, bound.max_bytes / 1e6, bounded.peak_feature_bytes() / 1e6,
              bounded.features_freed(), bounded.features_again());
  EXPECT_GT(bounded.features_freed(), 10);
  EXPECT_GT(bounded.features_again(), 0);  // the second and third lines came back to the first
  // Past the bound by at most what one Add brings: its 5 new frames and those extracted again.
  EXPECT_LT(bounded.peak_feature_bytes(), unbounded.peak_feature_bytes() * 7 / 10);
  EXPECT_LE(bounded.feature_bytes(), bound.max_bytes);

  // The same pairs, the same solution.
  EXPECT_GE(all.registered_cross, 5);
  EXPECT_EQ(some.registered_cross, all.registered_cross);
  EXPECT_EQ(some.registered_along, all.registered_along);
  ASSERT_EQ(some.poses.size(), all.poses.size());
  double worst_m = 0;
  for (size_t i = 0; i < all.poses.size(); ++i)
    worst_m = std::max(
        worst_m, std::hypot(some.poses[i].east_m - all.poses[i].east_m, some.poses[i].north_m - all.poses[i].north_m));
  EXPECT_LT(worst_m, 1e-9);

  bounded.FreeFeatures();  // the worker is done
  EXPECT_EQ(bounded.feature_bytes(), 0u);
}

}  // namespace
}  // namespace seamap
