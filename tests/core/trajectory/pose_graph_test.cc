#include "core/trajectory/pose_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/LU>

#include "core/util/error.h"

namespace seamap {
namespace {

double Wrap(double angle_rad) {
  return std::atan2(std::sin(angle_rad), std::cos(angle_rad));
}

double Radians(double degrees) {
  return degrees * M_PI / 180;
}

struct Survey {
  std::vector<PlanarPose> truth, nav;
  std::vector<double> time_s;
  std::vector<PairConstraint> pairs;
  int per_line = 0;
  int Index(int line, int k) const { return line * per_line + k; }
};

// The pair a perfect registration would measure between truth poses i and j.
PairConstraint ExactPair(const std::vector<PlanarPose>& truth, int i, int j, bool along_track, double sigma_m,
                         double sigma_rad) {
  const PlanarPose& a = truth[i];
  const PlanarPose& b = truth[j];
  const double d_east_m = b.east_m - a.east_m, d_north_m = b.north_m - a.north_m;
  const double c = std::cos(a.heading_rad), s = std::sin(a.heading_rad);
  PairConstraint pair;
  pair.i = i;
  pair.j = j;
  pair.dt_east_m = c * d_east_m - s * d_north_m;  // Rot(-psi_i)(t_j - t_i)
  pair.dt_north_m = s * d_east_m + c * d_north_m;
  pair.dheading_rad = Wrap(b.heading_rad - a.heading_rad);
  pair.covariance = Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
  pair.along_track = along_track;
  return pair;
}

struct SurveySpec {
  int lines = 3, per_line = 40;
  double spacing_m = 0.3, line_gap_m = 1.0, frame_dt_s = 0.5, turn_s = 10;
  double drift_east_m_per_s = 0.006, drift_north_m_per_s = -0.004;  // ~0.43 m/min
  int cross_every = 3;     // one cross-line pair per this many frames, plus diagonals
  int diagonal_every = 0;  // extra (k, k'+1) cross pairs every this many frames; 0 = none
  double pair_sigma_m = 1e-5, pair_sigma_rad = 1e-6;
};

// Lawnmower: even lines head north, odd lines south (headings wrapped, so the
// south lines cross +-pi), a small weave in heading and east; the navigation
// drifts linearly in position and carries a small heading error.
Survey MakeSurvey(const SurveySpec& spec) {
  Survey survey;
  survey.per_line = spec.per_line;
  for (int line = 0; line < spec.lines; ++line) {
    const bool north = line % 2 == 0;
    for (int k = 0; k < spec.per_line; ++k) {
      const double along_m = (north ? k : spec.per_line - 1 - k) * spec.spacing_m;
      PlanarPose truth;
      truth.east_m = line * spec.line_gap_m + 0.01 * std::sin(0.2 * k + line);
      truth.north_m = along_m;
      truth.heading_rad = Wrap((north ? 0 : M_PI) + 0.02 * std::sin(0.3 * k + line));
      const double t_s = (line * spec.per_line + k) * spec.frame_dt_s + line * spec.turn_s;
      PlanarPose nav = truth;
      nav.east_m += spec.drift_east_m_per_s * t_s;
      nav.north_m += spec.drift_north_m_per_s * t_s;
      nav.heading_rad = Wrap(truth.heading_rad + 0.003 * std::sin(0.7 * k + 2 * line));
      survey.truth.push_back(truth);
      survey.nav.push_back(nav);
      survey.time_s.push_back(t_s);
    }
  }
  for (int line = 0; line < spec.lines; ++line) {
    for (int k = 0; k < spec.per_line; ++k) {
      const int i = survey.Index(line, k);
      for (int step : {1, 2}) {
        if (k + step < spec.per_line) {
          survey.pairs.push_back(ExactPair(survey.truth, i, i + step, true, spec.pair_sigma_m, spec.pair_sigma_rad));
        }
      }
      if (line + 1 == spec.lines) continue;
      const int facing = spec.per_line - 1 - k;  // the next line runs the other way
      if (k % spec.cross_every == 0) {
        survey.pairs.push_back(
            ExactPair(survey.truth, i, survey.Index(line + 1, facing), false, spec.pair_sigma_m, spec.pair_sigma_rad));
      }
      if (spec.diagonal_every > 0 && k % spec.diagonal_every == 0 && facing + 1 < spec.per_line) {
        survey.pairs.push_back(ExactPair(survey.truth, i, survey.Index(line + 1, facing + 1), false, spec.pair_sigma_m,
                                         spec.pair_sigma_rad));
      }
    }
  }
  return survey;
}

// The best-fitting rigid motion p -> Rot(phi) p + c applied to `poses` (headings turn by phi).
std::vector<PlanarPose> AlignRigid(const std::vector<PlanarPose>& poses, const std::vector<PlanarPose>& target) {
  const double n = poses.size();
  double pe = 0, pn = 0, qe = 0, qn = 0;
  for (size_t k = 0; k < poses.size(); ++k) {
    pe += poses[k].east_m / n, pn += poses[k].north_m / n;
    qe += target[k].east_m / n, qn += target[k].north_m / n;
  }
  double dot = 0, cross = 0;
  for (size_t k = 0; k < poses.size(); ++k) {
    const double ae = poses[k].east_m - pe, an = poses[k].north_m - pn;
    const double be = target[k].east_m - qe, bn = target[k].north_m - qn;
    dot += be * ae + bn * an;
    cross += be * an - bn * ae;
  }
  const double phi = std::atan2(cross, dot), c = std::cos(phi), s = std::sin(phi);
  std::vector<PlanarPose> aligned(poses.size());
  for (size_t k = 0; k < poses.size(); ++k) {
    const double ae = poses[k].east_m - pe, an = poses[k].north_m - pn;
    aligned[k] = {qe + c * ae + s * an, qn - s * ae + c * an, poses[k].heading_rad + phi};
  }
  return aligned;
}

double MaxPositionError(const std::vector<PlanarPose>& a, const std::vector<PlanarPose>& b) {
  double worst = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    worst = std::max(worst, std::hypot(a[k].east_m - b[k].east_m, a[k].north_m - b[k].north_m));
  }
  return worst;
}

double MaxHeadingError(const std::vector<PlanarPose>& a, const std::vector<PlanarPose>& b) {
  double worst = 0;
  for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(Wrap(a[k].heading_rad - b[k].heading_rad)));
  return worst;
}

double RmsPositionError(const std::vector<PlanarPose>& a, const std::vector<PlanarPose>& b) {
  double sum = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    sum += std::pow(a[k].east_m - b[k].east_m, 2) + std::pow(a[k].north_m - b[k].north_m, 2);
  }
  return std::sqrt(sum / a.size());
}

int Count(const std::vector<bool>& flags) {
  return static_cast<int>(std::count(flags.begin(), flags.end(), true));
}

TEST(PoseGraph, ExactPairsRecoverTheShapeAndBeatTheNavigation) {
  const Survey survey = MakeSurvey({});
  const PoseGraphResult result = SolvePoseGraph(survey.nav, survey.time_s, survey.pairs, {});
  ASSERT_EQ(result.poses.size(), survey.truth.size());
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(Count(result.pair_rejected), 0);
  EXPECT_EQ(Count(result.nav_only), 0);
  EXPECT_LT(result.cost_after, result.cost_before);

  const std::vector<PlanarPose> aligned = AlignRigid(result.poses, survey.truth);
  EXPECT_LT(MaxPositionError(aligned, survey.truth), 1e-4);
  EXPECT_LT(MaxHeadingError(aligned, survey.truth), 1e-6);
  // The drifting priors set the gauge; early frames anchor it near the truth.
  EXPECT_LT(RmsPositionError(result.poses, survey.truth), RmsPositionError(survey.nav, survey.truth));
  EXPECT_LT(MaxPositionError(result.poses, survey.truth), MaxPositionError(survey.nav, survey.truth));
}

TEST(PoseGraph, OneWrongPairIsRejectedAndChangesNothing) {
  const Survey survey = MakeSurvey({});
  const PoseGraphResult clean = SolvePoseGraph(survey.nav, survey.time_s, survey.pairs, {});
  // A cross-line pair (few of them hold the lines together) and an along-track one.
  for (bool along_track : {false, true}) {
    SCOPED_TRACE(along_track ? "along-track" : "cross-line");
    std::vector<PairConstraint> pairs = survey.pairs;
    size_t wrong = 0;
    while (pairs[wrong].along_track != along_track || pairs[wrong].i < survey.per_line) ++wrong;
    pairs[wrong].dt_east_m += 0.3;  // 0.5 m off
    pairs[wrong].dt_north_m -= 0.4;
    pairs[wrong].dheading_rad += Radians(10);

    const PoseGraphResult result = SolvePoseGraph(survey.nav, survey.time_s, pairs, {});
    EXPECT_TRUE(result.converged);
    ASSERT_EQ(result.pair_rejected.size(), pairs.size());
    EXPECT_TRUE(result.pair_rejected[wrong]);
    EXPECT_EQ(Count(result.pair_rejected), 1);
    EXPECT_EQ(Count(result.nav_only), 0);  // both frames keep other pairs
    EXPECT_LT(MaxPositionError(result.poses, clean.poses), 0.5e-3);
    EXPECT_LT(MaxHeadingError(result.poses, clean.poses), 1e-6);
  }
}

TEST(PoseGraph, WithoutPairsTheNavigationComesBackUnchanged) {
  const Survey survey = MakeSurvey({});
  const PoseGraphResult result = SolvePoseGraph(survey.nav, survey.time_s, {}, {});
  ASSERT_EQ(result.poses.size(), survey.nav.size());
  for (size_t i = 0; i < survey.nav.size(); ++i) {
    EXPECT_EQ(result.poses[i].east_m, survey.nav[i].east_m);
    EXPECT_EQ(result.poses[i].north_m, survey.nav[i].north_m);
    EXPECT_EQ(result.poses[i].heading_rad, survey.nav[i].heading_rad);
  }
  EXPECT_EQ(Count(result.nav_only), static_cast<int>(survey.nav.size()));
  EXPECT_TRUE(result.pair_rejected.empty());
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.iterations, 0);
}

TEST(PoseGraph, AllPairsRejectedFallsBackOntoTheNavigation) {
  const Survey survey = MakeSurvey({});
  std::vector<PairConstraint> pairs = {survey.pairs[0]};
  pairs[0].dt_north_m += 1.0;  // alone and far off: rejected, nothing left
  const PoseGraphResult result = SolvePoseGraph(survey.nav, survey.time_s, pairs, {});
  EXPECT_TRUE(result.pair_rejected[0]);
  EXPECT_EQ(Count(result.nav_only), static_cast<int>(survey.nav.size()));
  EXPECT_EQ(MaxPositionError(result.poses, survey.nav), 0);
  EXPECT_EQ(MaxHeadingError(result.poses, survey.nav), 0);
}

TEST(PoseGraph, HeadingsAcrossTheWrapSolve) {
  Survey survey = MakeSurvey({});
  // The south line's truth headings already straddle +-pi; make the inputs awkward
  // too: navigation headings on other branches and pair headings unwrapped.
  int straddling = 0;
  for (int k = 0; k < survey.per_line; ++k) {
    const int i = survey.Index(1, k);
    straddling += survey.truth[i].heading_rad < 0;
    survey.nav[i].heading_rad += (k % 2 ? 2 * M_PI : -2 * M_PI);
  }
  ASSERT_GT(straddling, 5);
  ASSERT_LT(straddling, survey.per_line - 5);
  for (size_t k = 0; k < survey.pairs.size(); k += 2) survey.pairs[k].dheading_rad += 2 * M_PI;

  const PoseGraphResult result = SolvePoseGraph(survey.nav, survey.time_s, survey.pairs, {});
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(Count(result.pair_rejected), 0);
  const std::vector<PlanarPose> aligned = AlignRigid(result.poses, survey.truth);
  EXPECT_LT(MaxPositionError(aligned, survey.truth), 1e-4);
  EXPECT_LT(MaxHeadingError(aligned, survey.truth), 1e-6);
  // Headings stay on the navigation's branch rather than jumping by 2 pi.
  for (size_t i = 0; i < survey.nav.size(); ++i) {
    EXPECT_LT(std::abs(result.poses[i].heading_rad - survey.nav[i].heading_rad), 0.1) << i;
  }
}

TEST(PoseGraph, AFrameWithoutPairsIsNavOnlyAndStaysBetweenItsNeighbours) {
  Survey survey = MakeSurvey({});
  const int lonely = survey.Index(1, 20);
  std::vector<PairConstraint> pairs;
  for (const PairConstraint& pair : survey.pairs) {
    if (pair.i != lonely && pair.j != lonely) pairs.push_back(pair);
  }
  ASSERT_LT(pairs.size(), survey.pairs.size());

  const PoseGraphResult result = SolvePoseGraph(survey.nav, survey.time_s, pairs, {});
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(Count(result.pair_rejected), 0);
  for (size_t i = 0; i < survey.nav.size(); ++i) EXPECT_EQ(result.nav_only[i], static_cast<int>(i) == lonely) << i;

  // Its neighbours are refined exactly; it follows them by the navigation's own
  // relative motion, pulled towards its drifted absolute fix (~0.29 m off, sigma
  // ~0.67 m) only by about 0.29 * (1 / 0.67^2) / (2 / 0.071^2) = 1.6 mm.
  const auto& p = result.poses;
  const auto& t = survey.truth;
  const double bend_east_m = (p[lonely].east_m - (p[lonely - 1].east_m + p[lonely + 1].east_m) / 2) -
                             (t[lonely].east_m - (t[lonely - 1].east_m + t[lonely + 1].east_m) / 2);
  const double bend_north_m = (p[lonely].north_m - (p[lonely - 1].north_m + p[lonely + 1].north_m) / 2) -
                              (t[lonely].north_m - (t[lonely - 1].north_m + t[lonely + 1].north_m) / 2);
  EXPECT_LT(std::hypot(bend_east_m, bend_north_m), 3e-3);
  for (int neighbour : {lonely - 1, lonely + 1}) {
    const double step_m = std::hypot(p[lonely].east_m - p[neighbour].east_m, p[lonely].north_m - p[neighbour].north_m);
    const double true_step_m =
        std::hypot(t[lonely].east_m - t[neighbour].east_m, t[lonely].north_m - t[neighbour].north_m);
    EXPECT_NEAR(step_m, true_step_m, 5e-3);
  }
  // Everything else keeps the shape.
  std::vector<PlanarPose> others, others_truth;
  for (size_t i = 0; i < t.size(); ++i) {
    if (static_cast<int>(i) == lonely) continue;
    others.push_back(p[i]);
    others_truth.push_back(t[i]);
  }
  EXPECT_LT(MaxPositionError(AlignRigid(others, others_truth), others_truth), 1e-4);
}

TEST(PoseGraph, CheckNamesTheBadOption) {
  const auto field_of = [](const PoseGraphOptions& options) {
    try {
      options.Check();
    } catch (const InputError& error) {
      return error.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(field_of({}), "(accepted)");
  PoseGraphOptions exact;
  exact.nav_sigma_m = exact.nav_drift_m_per_s = exact.heading_sigma_rad = 0;  // floored, not refused
  EXPECT_EQ(field_of(exact), "(accepted)");

  PoseGraphOptions bad;
  bad.nav_sigma_m = -0.1;
  EXPECT_EQ(field_of(bad), "nav_sigma_m");
  bad = {};
  bad.nav_drift_m_per_s = NAN;
  EXPECT_EQ(field_of(bad), "nav_drift_m_per_s");
  bad = {};
  bad.heading_sigma_rad = INFINITY;
  EXPECT_EQ(field_of(bad), "heading_sigma_rad");
  bad = {};
  bad.pair_loss_scale = 0;
  EXPECT_EQ(field_of(bad), "pair_loss_scale");
  bad = {};
  bad.prior_loss_scale = -3;
  EXPECT_EQ(field_of(bad), "prior_loss_scale");
  bad = {};
  bad.reject_chi2 = 0;
  EXPECT_EQ(field_of(bad), "reject_chi2");
  bad = {};
  bad.max_iterations = 0;
  EXPECT_EQ(field_of(bad), "max_iterations");
  bad = {};
  bad.threads = 0;
  EXPECT_EQ(field_of(bad), "threads");
}

TEST(PoseGraph, RefusesBadInputsNamingThem) {
  const Survey survey = MakeSurvey({});
  const auto field_of = [&](const std::vector<double>& time_s, const std::vector<PairConstraint>& pairs) {
    try {
      SolvePoseGraph(survey.nav, time_s, pairs, {});
    } catch (const InputError& error) {
      return error.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(field_of({1.0, 2.0}, {}), "time_s");
  std::vector<double> unsorted = survey.time_s;
  std::swap(unsorted[3], unsorted[4]);
  EXPECT_EQ(field_of(unsorted, {}), "time_s[4]");

  std::vector<PairConstraint> pairs = {survey.pairs[0]};
  pairs[0].j = static_cast<int>(survey.nav.size());
  EXPECT_EQ(field_of(survey.time_s, pairs), "pairs[0].j");
  pairs = {survey.pairs[0], survey.pairs[1]};
  pairs[1].covariance(2, 2) = -1e-12;
  EXPECT_EQ(field_of(survey.time_s, pairs), "pairs[1].covariance");
  pairs[1].covariance = Eigen::Matrix3d::Identity();
  pairs[1].covariance(0, 1) = 0.5;  // not symmetric
  EXPECT_EQ(field_of(survey.time_s, pairs), "pairs[1].covariance");
}

TEST(PoseGraph, WhitenedSquaredNormIsTheMahalanobisDistance) {
  PairConstraint pair;
  pair.i = 0;
  pair.j = 1;
  pair.dt_east_m = 1.0;
  pair.dheading_rad = Radians(179);
  pair.covariance << 0.04, 0.01, 0, 0.01, 0.09, 0.002, 0, 0.002, 0.01;
  const PlanarPose a{5, 5, Radians(90)};  // facing east: the pair's "east" is the world's south
  const PlanarPose b{5.1, 3.8, Radians(-90)};
  const Eigen::Vector3d r(1.2 - 1.0, 0.1 - 0.0, Radians(1));  // -359 deg wraps to 1
  EXPECT_NEAR(PairWhitenedSquaredNorm(pair, a, b), r.dot(pair.covariance.inverse() * r), 1e-9);
}

// The survey of the size: 12 lines of 60 frames, ~2200 pairs, noisy
// navigation and 1 % wrong pairs. Correctness is asserted; the time is printed.
TEST(PoseGraph, ScalesToAWholeSurvey) {
  SurveySpec spec;
  spec.lines = 12;
  spec.per_line = 60;
  spec.cross_every = 1;
  spec.diagonal_every = 4;
  spec.pair_sigma_m = 1e-4;
  spec.pair_sigma_rad = 1e-5;
  Survey survey = MakeSurvey(spec);
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0, 1);
  for (PlanarPose& nav : survey.nav) {
    nav.east_m += 0.02 * noise(random);
    nav.north_m += 0.02 * noise(random);
    nav.heading_rad += Radians(0.5) * noise(random);
  }
  std::vector<bool> corrupted(survey.pairs.size(), false);
  std::uniform_int_distribution<size_t> pick(0, survey.pairs.size() - 1);
  std::uniform_real_distribution<double> offset_m(0.2, 1.0), angle(0, 2 * M_PI), turn_deg(5, 20);
  for (int n = 0; n < static_cast<int>(survey.pairs.size()) / 100; ++n) {
    const size_t k = pick(random);
    const double direction = angle(random), size_m = offset_m(random);
    survey.pairs[k].dt_east_m += size_m * std::cos(direction);
    survey.pairs[k].dt_north_m += size_m * std::sin(direction);
    survey.pairs[k].dheading_rad += Radians(turn_deg(random)) * (n % 2 ? 1 : -1);
    corrupted[k] = true;
  }
  ASSERT_EQ(survey.nav.size(), 720u);
  ASSERT_GT(survey.pairs.size(), 2100u);

  const auto start = std::chrono::steady_clock::now();
  const PoseGraphResult result = SolvePoseGraph(survey.nav, survey.time_s, survey.pairs, {});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("[ timing ] %zu poses, %zu pairs (%d wrong): %.3f s, %d iterations, %s\n", survey.nav.size(),
              survey.pairs.size(), Count(corrupted), seconds, result.iterations, result.linear_solver.c_str());

  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.pair_rejected, corrupted);
  EXPECT_EQ(Count(result.nav_only), 0);
  const std::vector<PlanarPose> aligned = AlignRigid(result.poses, survey.truth);
  EXPECT_LT(MaxPositionError(aligned, survey.truth), 1e-4);
  EXPECT_LT(MaxHeadingError(aligned, survey.truth), 1e-6);
  EXPECT_LT(RmsPositionError(result.poses, survey.truth), RmsPositionError(survey.nav, survey.truth));
}

}  // namespace
}  // namespace seamap
