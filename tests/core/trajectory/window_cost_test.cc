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

namespace seamap {
namespace {

constexpr double kSeaDepthM = 30;
constexpr int kLaneFrames = 40;

CameraModel Camera() {
  CameraModel c;
  c.width = 480;
  c.height = 360;
  c.fx = c.fy = 420;
  c.cx = 239.5;
  c.cy = 179.5;
  return c;
}

double SeabedUp(double east, double north) {
  return -kSeaDepthM + 0.15 * std::sin(1.7 * east + 0.3) * std::cos(1.1 * north) +
         0.1 * std::sin(2.9 * north - 0.8 * east);
}

// A 4-beam DVL (beams 30 deg off vertical): the mean vertical range of its beams.
double DvlAltitude(const VehiclePose& pose) {
  const Eigen::Matrix3d r_nb = NedFromBody(pose);
  double sum = 0;
  for (int b = 0; b < 4; ++b) {
    const double az = (45 + 90 * b) * M_PI / 180, tilt = 30 * M_PI / 180;
    const Eigen::Vector3d ray =
        r_nb * Eigen::Vector3d(std::cos(az) * std::sin(tilt), std::sin(az) * std::sin(tilt), std::cos(tilt));
    double range = 2;
    for (int it = 0; it < 50; ++it) {
      const double t = range / ray.z();
      range = -pose.depth_m - SeabedUp(pose.east_m + t * ray.y(), pose.north_m + t * ray.x());
    }
    sum += range;
  }
  return sum / 4;
}

bool Project(const CameraModel& camera, const VehiclePose& pose, const Eigen::Vector3d& enu, cv::Point2f* px) {
  const Eigen::Vector3d centre(pose.north_m, pose.east_m, pose.depth_m);
  const Eigen::Vector3d d =
      NedFromCamera(camera, pose).transpose() * (Eigen::Vector3d(enu.y(), enu.x(), -enu.z()) - centre);
  if (d.z() <= 0) return false;
  *px = cv::Point2f(static_cast<float>(camera.fx * d.x() / d.z() + camera.cx),
                    static_cast<float>(camera.fy * d.y() / d.z() + camera.cy));
  return px->x >= 0 && px->y >= 0 && px->x < camera.width && px->y < camera.height;
}

// A window of a longer survey: four lawnmower lanes 0.9 m apart at 2 m over
// 0.25 m of relief, pitch and roll of 3 deg, the navigation drifting 1 m/min
// with a depth sensor too coarse to place the vehicle over the seabed
// (0.3 m). The first two lanes were solved by the window before: held at the
// truth. The last two start at the navigation.
struct Window {
  std::vector<VehiclePose> truth;
  std::vector<SurveyBundleFrame> frames;
  std::vector<Eigen::Vector3d> points_start;
  std::vector<SurveyBundleObservation> observations;
  int held = 0;
};

Window MakeWindow() {
  constexpr int kLanes = 4, kHeldLanes = 2;
  Window s;
  const CameraModel camera = Camera();
  std::mt19937 rng(41);
  std::normal_distribution<double> unit(0, 1);
  const double speed = 0.5, fps = 5;
  for (int lane = 0; lane < kLanes; ++lane)
    for (int k = 0; k < kLaneFrames; ++k) {
      VehiclePose p;
      const double along = k * speed / fps;
      p.east_m = 0.9 * lane;
      p.north_m = lane % 2 == 0 ? along : 3.9 - along;
      p.heading_deg = lane % 2 == 0 ? 0 : 180;
      const int i = static_cast<int>(s.truth.size());
      p.pitch_deg = 3 * std::sin(0.3 * i);
      p.roll_deg = 3 * std::cos(0.23 * i);
      p.altitude_m = 2 + 0.1 * std::sin(0.1 * i);
      p.depth_m = -(SeabedUp(p.east_m, p.north_m) + p.altitude_m);
      p.altitude_m = DvlAltitude(p);
      s.truth.push_back(p);
    }
  const double drift_m_per_s = 1.0 / 60;
  for (size_t i = 0; i < s.truth.size(); ++i) {
    SurveyBundleFrame f;
    f.time_s = i / fps + (i / kLaneFrames) * 5.0;  // turns take 5 s
    f.nav = s.truth[i];
    f.nav.east_m += 0.6 * drift_m_per_s * f.time_s;
    f.nav.north_m += 0.8 * drift_m_per_s * f.time_s;
    f.nav.depth_m += 0.3 * unit(rng);
    f.nav.heading_deg += 0.3 * unit(rng);
    f.nav.pitch_deg += 0.2 * unit(rng);
    f.nav.roll_deg += 0.2 * unit(rng);
    f.fixed = static_cast<int>(i) < kHeldLanes * kLaneFrames;
    f.start = f.fixed ? s.truth[i] : f.nav;
    s.held += f.fixed;
    s.frames.push_back(f);
  }
  std::uniform_real_distribution<double> east(-0.8, 0.9 * (kLanes - 1) + 0.8), north(-0.8, 4.7);
  for (int k = 0; k < 140 * kLanes; ++k) {
    const double e = east(rng), n = north(rng);
    const Eigen::Vector3d point(e, n, SeabedUp(e, n));
    std::vector<SurveyBundleObservation> seen;
    for (size_t i = 0; i < s.truth.size(); ++i) {
      cv::Point2f px;
      if (!Project(camera, s.truth[i], point, &px)) continue;
      px.x += static_cast<float>(0.3 * unit(rng));
      px.y += static_cast<float>(0.3 * unit(rng));
      seen.push_back({static_cast<int>(i), static_cast<int>(s.points_start.size()), px});
    }
    if (seen.size() < 2) continue;
    Eigen::Vector3d start = Eigen::Vector3d::Zero();
    for (const auto& o : seen) start += *FlatSeabedPoint(camera, s.frames[o.frame].start, o.ideal_px);
    s.points_start.push_back(start / seen.size());
    s.observations.insert(s.observations.end(), seen.begin(), seen.end());
  }
  return s;
}

SurveyBundleOptions WindowOptions() {
  SurveyBundleOptions options;
  options.nav_sigma_m = 0.005;
  options.nav_drift_m_per_s = 1.0 / 60;
  options.heading_sigma_rad = 0.5 * M_PI / 180;
  options.attitude_sigma_rad = 0.3 * M_PI / 180;
  options.altitude_sigma_m = 0.01;
  options.depth_sigma_m = 0.3;
  options.pixel_sigma = 0.3;
  options.threads = 1;
  return options;
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
