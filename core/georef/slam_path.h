#pragma once
// What the SLAM keyframes say about the motion before any fit: turns, legs,
// straightness and steadiness, the local direction of travel. SLAM has an
// unknown scale and arbitrary axes, so everything here is a ratio or an angle.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/georef/tum_trajectory.h"

namespace seamap {

struct SlamLeg {
  double start_s = 0, end_s = 0;  // first and last keyframe time of a run without turns
};

// A jump or a long gap inside one keyframe file: a SLAM reset the user may
// want to split into sub-maps.
struct SuspectedReset {
  int line = 0;
  std::string why;
};

class SlamPath {
 public:
  struct Options {
    double turn_window_s = 10;   // a turn: the course changes by more than
    double turn_angle_deg = 20;  // turn_angle_deg across turn_window_s
  };
  SlamPath(const std::vector<Keyframe>& keyframes, const Options& options);

  size_t size() const { return times_.size(); }
  double time(size_t i) const { return times_[i]; }
  const Eigen::Vector3d& position(size_t i) const { return positions_[i]; }
  const std::vector<Eigen::Vector3d>& positions() const { return positions_; }

  // Linear interpolation between keyframes, clamped at the ends.
  Eigen::Vector3d PositionAt(double time_s) const;
  // Unit chord over [t - half, t + half] clipped to [from_s, to_s]; zero when too short.
  Eigen::Vector3d DirectionAt(double time_s, double half_window_s, double from_s, double to_s) const;
  // SLAM units per second along the same chord.
  double SpeedAt(double time_s, double half_window_s, double from_s, double to_s) const;

  bool turning(size_t i) const { return turning_[i]; }
  int leg(size_t i) const { return leg_[i]; }  // -1 while turning
  const std::vector<SlamLeg>& legs() const { return legs_; }
  // Time since the last turn (or the start: the buoy's state then is unknown).
  double SinceTurn(size_t i) const { return since_turn_[i]; }

  // chord / arc length of the keyframes in [from_s, to_s]; 1 on a straight line.
  double Straightness(double from_s, double to_s) const;
  // Coefficient of variation of the keyframe-to-keyframe speeds in [from_s, to_s].
  double SpeedVariation(double from_s, double to_s) const;
  // SLAM noise per axis (SLAM units) from the scatter about neighbours.
  double NoiseSigma() const { return noise_sigma_; }

  std::vector<SuspectedReset> SuspectedResets() const;

 private:
  std::vector<double> times_;
  std::vector<int> lines_;
  std::vector<Eigen::Vector3d> positions_;
  std::vector<bool> turning_;
  std::vector<int> leg_;
  std::vector<SlamLeg> legs_;
  std::vector<double> since_turn_;
  double noise_sigma_ = 0;
};

}  // namespace seamap
