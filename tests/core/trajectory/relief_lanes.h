#pragma once
// A small lawnmower survey over relief for the windowed bundle's tests:
// lanes 0.9 m apart of kLaneFrames frames at 2 m over 0.25 m of relief,
// pitch and roll of 3 deg, a 4-beam DVL; the navigation drifting 1 m/min
// with noisy heading and attitude; seabed points seen with 0.3 px noise.
#include <cmath>
#include <random>
#include <vector>

#include "core/camera/frame_projector.h"
#include "core/trajectory/survey_bundle.h"

namespace seamap::relief_lanes {

constexpr double kSeaDepthM = 30;
constexpr int kLaneFrames = 40;

inline CameraModel Camera() {
  CameraModel c;
  c.width = 480;
  c.height = 360;
  c.fx = c.fy = 420;
  c.cx = 239.5;
  c.cy = 179.5;
  return c;
}

inline double SeabedUp(double east, double north) {
  return -kSeaDepthM + 0.15 * std::sin(1.7 * east + 0.3) * std::cos(1.1 * north) +
         0.1 * std::sin(2.9 * north - 0.8 * east);
}

// A 4-beam DVL (beams 30 deg off vertical) over that seabed: the mean vertical range of its beams.
inline double DvlAltitude(const VehiclePose& pose) {
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

inline bool Project(const CameraModel& camera, const VehiclePose& pose, const Eigen::Vector3d& enu, cv::Point2f* px) {
  const Eigen::Vector3d centre(pose.north_m, pose.east_m, pose.depth_m);
  const Eigen::Vector3d d =
      NedFromCamera(camera, pose).transpose() * (Eigen::Vector3d(enu.y(), enu.x(), -enu.z()) - centre);
  if (d.z() <= 0) return false;
  *px = cv::Point2f(static_cast<float>(camera.fx * d.x() / d.z() + camera.cx),
                    static_cast<float>(camera.fy * d.y() / d.z() + camera.cy));
  return px->x >= 0 && px->y >= 0 && px->x < camera.width && px->y < camera.height;
}

struct Lanes {
  std::vector<VehiclePose> truth;
  std::vector<SurveyBundleFrame> frames;
  std::vector<Eigen::Vector3d> points_truth, points_start;
  std::vector<SurveyBundleObservation> observations;
  int held = 0;  // frames held (fixed) at the truth, as a window's earlier frames
};

struct LanesOptions {
  int lanes = 5;
  unsigned seed = 38;
  double depth_noise_m = 0;  // the depth sensor's noise (0: exact)
  int held_lanes = 0;        // the first lanes held at the truth; the others start at the navigation
  int points = 0;            // seabed points drawn (those seen twice are kept); 0: 140 a lane
};

inline Lanes MakeLanes(const LanesOptions& o) {
  Lanes s;
  const CameraModel camera = Camera();
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> unit(0, 1);
  const double speed = 0.5, fps = 5;
  for (int lane = 0; lane < o.lanes; ++lane)
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
    if (o.depth_noise_m > 0) f.nav.depth_m += o.depth_noise_m * unit(rng);
    f.nav.heading_deg += 0.3 * unit(rng);
    f.nav.pitch_deg += 0.2 * unit(rng);
    f.nav.roll_deg += 0.2 * unit(rng);
    f.fixed = static_cast<int>(i) < o.held_lanes * kLaneFrames;
    f.start = f.fixed ? s.truth[i] : f.nav;
    s.held += f.fixed;
    s.frames.push_back(f);
  }
  std::uniform_real_distribution<double> east(-0.8, 0.9 * (o.lanes - 1) + 0.8), north(-0.8, 4.7);
  for (int k = 0; k < (o.points > 0 ? o.points : 140 * o.lanes); ++k) {
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
    for (const auto& obs : seen) start += *FlatSeabedPoint(camera, s.frames[obs.frame].start, obs.ideal_px);
    s.points_start.push_back(start / seen.size());
    s.points_truth.push_back(point);
    s.observations.insert(s.observations.end(), seen.begin(), seen.end());
  }
  return s;
}

// The bundle's options for these lanes: the noise they were made with.
inline SurveyBundleOptions LanesBundleOptions(const LanesOptions& o) {
  SurveyBundleOptions options;
  options.nav_sigma_m = 0.005;
  options.nav_drift_m_per_s = 1.0 / 60;
  options.heading_sigma_rad = 0.5 * M_PI / 180;
  options.attitude_sigma_rad = 0.3 * M_PI / 180;
  options.altitude_sigma_m = 0.01;
  options.depth_sigma_m = o.depth_noise_m > 0 ? o.depth_noise_m : 0.01;
  options.pixel_sigma = 0.3;
  options.threads = 1;
  return options;
}

}  // namespace seamap::relief_lanes
