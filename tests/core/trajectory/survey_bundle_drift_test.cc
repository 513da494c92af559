// The bundle adjustment against a navigation that drifts steadily (issue 29,
// refinement in 3-D: the ATE). A constant drift is what the priors must not
// take for the vehicle's motion: with the drift estimated as unknowns of time
// the map stays where the navigation started; with the pose graph's absolute
// priors (sigma growing with time, each frame on its own) the first frames,
// trusted most, follow the drift and carry the whole map off with them.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/camera/frame_projector.h"
#include "core/trajectory/survey_bundle.h"
#include "core/util/error.h"
#include "tests/core/trajectory/synthetic_seabed.h"

namespace seamap {
namespace {

using testing_seabed::Relief;

struct DriftScene {
  CameraModel camera = testing_seabed::SmallCamera();
  std::vector<VehiclePose> truth;
  std::vector<SurveyBundleFrame> frames;
  std::vector<Eigen::Vector3d> points_start;
  std::vector<SurveyBundleObservation> observations;
};

// Four lanes of 6 m, 0.75 m apart, a frame every 0.1 m (5 frames/s at
// 0.5 m/s) at 2 m over 0.1 m rms relief; the navigation drifts 0.5 m/min
// along the first lane (north-east) with 5 mm of white noise, as the
// simulator's `--nav-drift 0.5 --nav-noise 0.005`.
DriftScene MakeDriftScene() {
  DriftScene s;
  const Relief relief(0.1, 29);
  s.truth = testing_seabed::Lawnmower(relief, 4, 6, 0.75, 0.1);
  std::mt19937 rng(7);
  std::normal_distribution<double> unit(0, 1);
  const double drift_m_per_s = 0.5 / 60, fps = 5;
  for (size_t i = 0; i < s.truth.size(); ++i) {
    SurveyBundleFrame f;
    f.time_s = i / fps;
    f.nav = s.truth[i];
    f.nav.east_m += 0.3 * drift_m_per_s * f.time_s + 0.005 * unit(rng);
    f.nav.north_m += 0.95 * drift_m_per_s * f.time_s + 0.005 * unit(rng);
    f.nav.heading_deg += 0.3 * unit(rng);
    f.start = f.nav;
    s.frames.push_back(f);
  }
  std::uniform_real_distribution<double> east(-0.7, 2.95), north(-0.5, 6.5);
  for (int k = 0; k < 1500; ++k) {
    const double e = east(rng), n = north(rng);
    const Eigen::Vector3d point(e, n, relief.Up(e, n));
    std::vector<SurveyBundleObservation> seen;
    for (size_t i = 0; i < s.truth.size(); ++i) {
      const VehiclePose& p = s.truth[i];
      const Eigen::Vector3d d =
          NedFromCamera(s.camera, p).transpose() *
          (Eigen::Vector3d(point.y(), point.x(), -point.z()) - Eigen::Vector3d(p.north_m, p.east_m, p.depth_m));
      if (d.z() <= 0) continue;
      const cv::Point2f px(static_cast<float>(s.camera.fx * d.x() / d.z() + s.camera.cx + 0.3 * unit(rng)),
                           static_cast<float>(s.camera.fy * d.y() / d.z() + s.camera.cy + 0.3 * unit(rng)));
      if (px.x < 0 || px.y < 0 || px.x > s.camera.width - 1 || px.y > s.camera.height - 1) continue;
      seen.push_back({static_cast<int>(i), static_cast<int>(s.points_start.size()), px});
    }
    if (seen.size() < 3) continue;
    Eigen::Vector3d start = Eigen::Vector3d::Zero();
    for (const auto& o : seen) start += *FlatSeabedPoint(s.camera, s.frames[o.frame].nav, o.ideal_px);
    s.points_start.push_back(start / static_cast<double>(seen.size()));
    s.observations.insert(s.observations.end(), seen.begin(), seen.end());
  }
  return s;
}

SurveyBundleOptions DriftOptions() {
  SurveyBundleOptions o;
  o.nav_sigma_m = 0.005;
  o.nav_drift_m_per_s = 0.5 / 60;
  o.heading_sigma_rad = 0.3 * M_PI / 180;
  o.attitude_sigma_rad = 0.2 * M_PI / 180;
  o.depth_sigma_m = 0.01;
  o.altitude_sigma_m = 0.01;
  o.dvl_beam_angle_deg = 0;  // the scene's altitude is the seabed straight below
  o.pixel_sigma = 0.3;
  o.threads = 1;
  return o;
}

// RMS horizontal distance to the truth, metres: the absolute trajectory error.
double Ate(const std::vector<VehiclePose>& poses, const std::vector<VehiclePose>& truth) {
  double sum = 0;
  for (size_t i = 0; i < truth.size(); ++i)
    sum += std::pow(poses[i].east_m - truth[i].east_m, 2) + std::pow(poses[i].north_m - truth[i].north_m, 2);
  return std::sqrt(sum / truth.size());
}

TEST(SurveyBundleDrift, TheDriftIsEstimatedAndTheMapStaysWhereTheNavigationStarted) {
  const DriftScene s = MakeDriftScene();
  ASSERT_GT(s.points_start.size(), 800u);
  std::vector<VehiclePose> nav;
  for (const auto& f : s.frames) nav.push_back(f.nav);

  SurveyBundleOptions old_priors = DriftOptions();
  old_priors.drift_knot_s = 0;
  const SurveyBundleResult before = SolveSurveyBundle(s.frames, s.camera, s.points_start, s.observations, old_priors);
  const SurveyBundleResult now = SolveSurveyBundle(s.frames, s.camera, s.points_start, s.observations, DriftOptions());
  const double ate_nav = Ate(nav, s.truth), ate_before = Ate(before.poses, s.truth), ate_now = Ate(now.poses, s.truth);
  std::printf("ATE: navigation %.1f mm, absolute priors by time %.1f mm, drift estimated %.1f mm\n", 1000 * ate_nav,
              1000 * ate_before, 1000 * ate_now);
  EXPECT_GT(ate_nav, 0.1);
  // Measured 17.1 mm (the map carried off by its first frames) and 3.8 mm.
  EXPECT_GT(ate_before, 0.010);
  EXPECT_LT(ate_now, 0.007);
  EXPECT_LT(now.rms_px_after, 0.5);
}

// A wrong match triangulated above the vehicle is behind every camera at the
// start: Ceres cannot evaluate its residuals there and used to stop before the
// first iteration (a 720-frame rugged survey, seed 2, refined nothing).
TEST(SurveyBundleDrift, APointBehindTheCamerasAtTheStartIsDroppedNotFatal) {
  DriftScene s = MakeDriftScene();
  s.points_start[0].z() = 0;  // the sea surface: 10 m above the vehicles
  const SurveyBundleResult r = SolveSurveyBundle(s.frames, s.camera, s.points_start, s.observations, DriftOptions());
  EXPECT_GT(r.iterations, 2);
  EXPECT_LT(r.rms_px_after, 0.5);
  EXPECT_EQ(r.points[0].views, 0);
  std::vector<VehiclePose> truth = s.truth;
  EXPECT_LT(Ate(r.poses, truth), 0.007);
}

TEST(SurveyBundleDrift, AKnotSpacingThatIsNoNumberIsAnErrorNamingIt) {
  SurveyBundleOptions o = DriftOptions();
  for (double bad : {-1.0, std::nan("")}) {
    o.drift_knot_s = bad;
    try {
      SolveSurveyBundle({}, testing_seabed::SmallCamera(), {}, {}, o);
      FAIL() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("drift_knot_s"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace seamap
