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
};

}  // namespace seamap
