#pragma once
// What the planar pose graph (pose_graph.cc) and the bundle adjustment
// (survey_bundle.cc) both weigh the navigation with: the stated-noise
// floors, angle wrapping for automatic differentiation, and the relative and
// absolute position priors on a pose block whose first two entries are east,
// north.
#include <cmath>

namespace seamap {

// Floors keep exact navigation (stated noise 0) from dividing by zero.
constexpr double kNavSigmaFloorM = 1e-3;
constexpr double kHeadingSigmaFloorRad = 0.01 * M_PI / 180;

// atan2(sin, cos) is smooth for automatic differentiation; fmod is not.
template <typename T>
T WrapAngle(const T& angle_rad) {
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(angle_rad), cos(angle_rad));
}

// The navigation's absolute position, trusted less as drift accumulates.
struct NavPositionResidual {
  double east_m, north_m, inv_sigma_m;

  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    residual[0] = (pose[0] - east_m) * inv_sigma_m;
    residual[1] = (pose[1] - north_m) * inv_sigma_m;
    return true;
  }
};

// Consecutive frames move as the navigation says, up to its noise and drift;
// kHeading: the heading's index in the pose block (2 planar, 3 in the bundle).
template <int kHeading>
struct NavRelativeResidual {
  double d_east_m, d_north_m, d_heading_rad, inv_sigma_m, inv_sigma_heading_rad;

  template <typename T>
  bool operator()(const T* a, const T* b, T* residual) const {
    residual[0] = ((b[0] - a[0]) - d_east_m) * inv_sigma_m;
    residual[1] = ((b[1] - a[1]) - d_north_m) * inv_sigma_m;
    residual[2] = WrapAngle((b[kHeading] - a[kHeading]) - d_heading_rad) * inv_sigma_heading_rad;
    return true;
  }
};

// The navigation as the truth plus a drift that varies slowly with time plus
// white noise: its position less the drift, interpolated linearly between the
// two knots around the frame's time, against the pose, over the noise alone.
struct DriftedNavPositionResidual {
  double east_m, north_m, share_next, inv_sigma_m;  // share_next: the frame's place between the knots, 0..1

  template <typename T>
  bool operator()(const T* pose, const T* drift, const T* drift_next, T* residual) const {
    residual[0] = (pose[0] + (1 - share_next) * drift[0] + share_next * drift_next[0] - east_m) * inv_sigma_m;
    residual[1] = (pose[1] + (1 - share_next) * drift[1] + share_next * drift_next[1] - north_m) * inv_sigma_m;
    return true;
  }
};

// The drift from one knot to the next, within what the drift rate allows.
struct NavDriftStepResidual {
  double inv_sigma_m;

  template <typename T>
  bool operator()(const T* drift, const T* drift_next, T* residual) const {
    residual[0] = (drift_next[0] - drift[0]) * inv_sigma_m;
    residual[1] = (drift_next[1] - drift[1]) * inv_sigma_m;
    return true;
  }
};

// The drift at the first knot: the navigation starts where the vehicle is, up to its noise.
struct NavDriftStartResidual {
  double inv_sigma_m;

  template <typename T>
  bool operator()(const T* drift, T* residual) const {
    residual[0] = drift[0] * inv_sigma_m;
    residual[1] = drift[1] * inv_sigma_m;
    return true;
  }
};

}  // namespace seamap
