// A window's cost (docs/BUNDLE_WINDOWS.md, "A window's cost"): a window of a
// longer survey, holding the frames earlier windows solved, solves its
// reduced system by conjugate gradients and must come out as the
// factorisation does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/camera/frame_projector.h"
#include "core/trajectory/survey_bundle.h"
#include "tests/core/trajectory/relief_lanes.h"

namespace seamap {
namespace {

using namespace relief_lanes;
using Window = Lanes;

// A window of a longer survey: four lanes (relief_lanes.h) with a depth
// sensor too coarse to place the vehicle over the seabed (0.3 m). The first
// two lanes were solved by the window before: held at the truth. The last
// two start at the navigation.
LanesOptions WindowLanes() {
  LanesOptions o;
  o.lanes = 4;
  o.seed = 41;
  o.depth_noise_m = 0.3;
  o.held_lanes = 2;
  return o;
}

Window MakeWindow() {
  return MakeLanes(WindowLanes());
}

SurveyBundleOptions WindowOptions() {
  return LanesBundleOptions(WindowLanes());
}

struct Errors {
  double horizontal_m = 0, vertical_m = 0;  // RMS over the solved frames, against the truth
};

Errors SolvedFramesError(const Window& s, const SurveyBundleResult& r) {
  Errors e;
  int n = 0;
  for (size_t i = 0; i < s.truth.size(); ++i) {
    if (s.frames[i].fixed) continue;
    e.horizontal_m +=
        std::pow(r.poses[i].east_m - s.truth[i].east_m, 2) + std::pow(r.poses[i].north_m - s.truth[i].north_m, 2);
    e.vertical_m += std::pow(r.poses[i].depth_m - s.truth[i].depth_m, 2);
    ++n;
  }
  e.horizontal_m = std::sqrt(e.horizontal_m / n);
  e.vertical_m = std::sqrt(e.vertical_m / n);
  return e;
}

TEST(WindowCost, ConjugateGradientsSolveAWindowAsTheFactorisationDoes) {
  // Windows solve their reduced system by preconditioned conjugate gradients
  // (inexact steps) instead of factoring it: the same answer, to well under
  // the solve's own error.
  const Window s = MakeWindow();
  SurveyBundleOptions options = WindowOptions();
  const SurveyBundleResult factored = SolveSurveyBundle(s.frames, Camera(), s.points_start, s.observations, options);
  options.iterative_schur = true;
  const SurveyBundleResult r = SolveSurveyBundle(s.frames, Camera(), s.points_start, s.observations, options);
  EXPECT_EQ(r.linear_solver, "ITERATIVE_SCHUR/SCHUR_JACOBI");
  EXPECT_NE(factored.linear_solver, r.linear_solver);
  EXPECT_TRUE(r.converged);
  double largest_difference_m = 0;
  for (size_t i = 0; i < s.truth.size(); ++i) {
    const VehiclePose &a = r.poses[i], &b = factored.poses[i];
    largest_difference_m =
        std::max(largest_difference_m, std::sqrt(std::pow(a.east_m - b.east_m, 2) + std::pow(a.north_m - b.north_m, 2) +
                                                 std::pow(a.depth_m - b.depth_m, 2)));
  }
  const Errors e = SolvedFramesError(s, r);
  std::printf(
      "conjugate gradients: horizontal %.2f mm, vertical %.2f mm, %d iterations (factored: %d); largest "
      "difference %.3f mm\n",
      1000 * e.horizontal_m, 1000 * e.vertical_m, r.iterations, factored.iterations, 1000 * largest_difference_m);
  EXPECT_LT(largest_difference_m, 0.0005);
  EXPECT_LT(e.horizontal_m, 0.004);
  EXPECT_LT(e.vertical_m, 0.0015);
}

}  // namespace
}  // namespace seamap
