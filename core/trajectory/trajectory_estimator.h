#pragma once
// The vehicle's trajectory estimated as frames arrive (causal: the same code
// runs offline in `seamap trajectory --mode vo|ekf` and live in `seamap replay
// --nav-mode vo|ekf`). The navigation filter (velocity_filter.h) predicts
// with the attitude as input and takes the visual odometry's body velocity
// and the depth; in `ekf` mode also the navigation's positions, gated. In
// `vo` mode the navigation's positions are used only for the first fix: the
// vehicle with no DVL or USBL.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/trajectory/frame_features.h"
#include "core/trajectory/velocity_filter.h"
#include "core/trajectory/visual_odometry.h"

namespace seamap {

enum class EstimatorMode { kVo, kEkf };
// "vo" | "ekf"; InputError naming `option` otherwise.
EstimatorMode ParseEstimatorMode(const std::string& text, const std::string& option);

struct EstimatorOptions {
  EstimatorMode mode = EstimatorMode::kEkf;
  VoOptions vo;
  VelocityFilterOptions filter;
  double nav_sigma_m = 0.05;  // the first fix's sigma, and ekf positions'
  // Frames further apart than this in time (a gap in the survey, or a clock
  // that jumped by a year) restart the filter at the navigation's pose
  // instead of predicting across the gap step by step.
  double max_gap_s = 60;
  void Check() const;
};

class TrajectoryEstimator {
 public:
  TrajectoryEstimator(const CameraModel& camera, const EstimatorOptions& options);

  // The next frame in time order: its features (nullptr when its image
  // cannot be read: the filter predicts on), time and navigation pose.
  // Returns the pose to place the frame with: the filter's position and
  // depth, the navigation's altitude and attitude.
  VehiclePose Add(const FrameFeatures* features, double time_s, const VehiclePose& nav);

  // What happened to the last frame Add placed, for the trajectory's flags
  // (';'-separated, "" when nothing): "restart_after_gap" (the filter
  // restarted there), "low_texture" (visual odometry could not use it),
  // "identical_photos" (the same photo as the last one: a frozen camera).
  const std::string& last_flags() const { return last_flags_; }
  // The gaps the filter restarted across: the frame's time and the gap, seconds.
  const std::vector<std::pair<double, double>>& gaps() const { return gaps_; }

  const VisualOdometry::Counts& vo_counts() const { return vo_.counts(); }
  const VelocityFilter::Counts& filter_counts() const { return filter_.counts(); }
  int frames() const { return frames_; }

 private:
  CameraModel camera_;
  EstimatorOptions options_;
  VisualOdometry vo_;
  VelocityFilter filter_;
  int frames_ = 0;
  double last_time_s_ = 0;
  Attitude last_attitude_;
  std::string last_flags_;
  std::vector<std::pair<double, double>> gaps_;
};

}  // namespace seamap
