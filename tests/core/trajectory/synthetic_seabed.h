#pragma once
// A small synthetic survey over relief for the seabed-track tests: a smooth
// random height field, seabed points scattered on it with SIFT-like 8-bit
// descriptors, and lawnmower frames whose features are the points' exact
// projections plus pixel noise, descriptor noise and distractors. No images:
// the geometry and the matching are tested without the detector.
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/trajectory/frame_features.h"
#include "core/trajectory/seabed_tracks.h"

namespace seamap::testing_seabed {

constexpr double kDepthM = 10;  // vehicle depth; the nominal seabed is at -12

// Sum of sinusoids, wavelengths 0.6-4 m, rms about `relief_rms_m`.
struct Relief {
  struct Wave {
    double kx, ky, phase, amplitude;
  };
  std::vector<Wave> waves;
  double base_up_m = -12;
  Relief(double relief_rms_m, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const int n = 12;
    for (int k = 0; k < n; ++k) {
      const double wavelength = 0.6 * std::pow(4 / 0.6, static_cast<double>(k) / (n - 1));
      const double dir = 2 * M_PI * u(rng);
      // Longer waves carry more height (a red spectrum), as real relief does.
      waves.push_back({2 * M_PI / wavelength * std::cos(dir), 2 * M_PI / wavelength * std::sin(dir), 2 * M_PI * u(rng),
                       wavelength});
    }
    double power = 0;
    for (const Wave& w : waves) power += w.amplitude * w.amplitude / 2;
    for (Wave& w : waves) w.amplitude *= relief_rms_m / std::sqrt(power);
  }
  double Up(double east, double north) const {
    double h = base_up_m;
    for (const Wave& w : waves) h += w.amplitude * std::sin(w.kx * east + w.ky * north + w.phase);
    return h;
  }
};

inline CameraModel SmallCamera() {
  CameraModel c;
  c.width = 320;
  c.height = 240;
  c.fx = c.fy = 240;
  c.cx = 159.5;
  c.cy = 119.5;
  return c;
}

// Lawnmower lanes running north then south, `lane_gap_m` apart, a frame
// every `step_m`, at constant depth; the altitude is measured to the seabed
// below the vehicle, as a DVL would.
inline std::vector<VehiclePose> Lawnmower(const Relief& relief, int lanes, double lane_length_m, double lane_gap_m,
                                          double step_m) {
  std::vector<VehiclePose> poses;
  for (int l = 0; l < lanes; ++l) {
    const int steps = static_cast<int>(lane_length_m / step_m);
    for (int s = 0; s <= steps; ++s) {
      VehiclePose p;
      p.east_m = l * lane_gap_m;
      p.north_m = l % 2 == 0 ? s * step_m : lane_length_m - s * step_m;
      p.heading_deg = l % 2 == 0 ? 0 : 180;
      p.depth_m = kDepthM;
      p.altitude_m = -kDepthM - relief.Up(p.east_m, p.north_m);
      poses.push_back(p);
    }
  }
  return poses;
}

struct ScenePoint {
  Eigen::Vector3d east_north_up_m;
  std::vector<uint8_t> descriptor;
  double east_speed_m_per_frame = 0;  // a moving object (fish): drifts with the frame index
};

struct Scene {
  CameraModel camera = SmallCamera();
  std::vector<VehiclePose> poses;
  std::vector<ScenePoint> points;
  double pixel_noise_px = 0.3;
  double distractor_share = 0.05;
  uint32_t seed = 1;

  std::vector<uint8_t> RandomDescriptor(std::mt19937* rng) const {
    std::uniform_int_distribution<int> d(0, 100);
    std::vector<uint8_t> out(128);
    for (auto& v : out) v = static_cast<uint8_t>(d(*rng));
    return out;
  }
  // Points on the relief, `per_m2` over the rectangle.
  void ScatterOnRelief(const Relief& relief, double e0, double e1, double n0, double n1, double per_m2) {
    std::mt19937 rng(seed * 7919u + 3);
    std::uniform_real_distribution<double> ue(e0, e1), un(n0, n1);
    const int n = static_cast<int>(per_m2 * (e1 - e0) * (n1 - n0));
    for (int k = 0; k < n; ++k) {
      const double e = ue(rng), no = un(rng);
      points.push_back({{e, no, relief.Up(e, no)}, RandomDescriptor(&rng)});
    }
  }
  FrameFeatures FeaturesOf(int frame) const {
    std::mt19937 rng(seed * 104729u + static_cast<uint32_t>(frame));
    std::normal_distribution<double> noise(0, pixel_noise_px);
    std::uniform_int_distribution<int> jitter(-4, 4);
    const TrackCamera view = TrackCameraOf(camera, poses[frame]);
    FrameFeatures f;
    std::vector<std::vector<uint8_t>> rows;
    for (const ScenePoint& p : points) {
      Eigen::Vector3d where = p.east_north_up_m;
      where.x() += p.east_speed_m_per_frame * frame;
      if ((where.head<2>() - view.centre_m.head<2>()).norm() > 3) continue;
      Eigen::Vector2d px;
      if (!ProjectToIdeal(camera, view, where, &px)) continue;
      px += Eigen::Vector2d(noise(rng), noise(rng));
      if (px.x() < 0 || px.y() < 0 || px.x() > camera.width - 1 || px.y() > camera.height - 1) continue;
      f.ideal_px.emplace_back(static_cast<float>(px.x()), static_cast<float>(px.y()));
      std::vector<uint8_t> d = p.descriptor;
      for (auto& v : d) v = static_cast<uint8_t>(std::clamp(v + jitter(rng), 0, 255));
      rows.push_back(d);
    }
    std::uniform_real_distribution<double> ux(0, camera.width - 1), uy(0, camera.height - 1);
    const int distractors = static_cast<int>(distractor_share * rows.size());
    for (int k = 0; k < distractors; ++k) {
      f.ideal_px.emplace_back(static_cast<float>(ux(rng)), static_cast<float>(uy(rng)));
      rows.push_back(RandomDescriptor(&rng));
    }
    f.descriptors = cv::Mat(static_cast<int>(rows.size()), 128, CV_8U);
    for (size_t k = 0; k < rows.size(); ++k)
      std::copy(rows[k].begin(), rows[k].end(), f.descriptors.ptr<uint8_t>(static_cast<int>(k)));
    return f;
  }
};

}  // namespace seamap::testing_seabed
