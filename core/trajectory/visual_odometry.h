#pragma once
// Monocular visual odometry with the altitude for scale (seed 003, section
// 2.1, with the changes of docs/specs "visual-odometry-ekf" 2.1-2.4): each
// frame is matched to a reference frame (SIFT, Lowe ratio 0.7); once the
// de-rotated parallax is worth measuring (5 % of the image width) or 2 s have
// passed, the motion between them (two_view.h) becomes one body-velocity
// measurement and the frame becomes the reference. Frames with too little
// texture or blur never become references; a vehicle that hovers gives a
// zero-velocity measurement; a pair where both models fail gives none.
#include <optional>
#include <string>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/trajectory/frame_features.h"
#include "core/trajectory/two_view.h"

namespace seamap {

struct VoOptions {
  FeatureOptions features = [] {
    FeatureOptions f;
    f.max_features = 1500;
    return f;
  }();
  double ratio = 0.7;              // Lowe's, the paper's
  double min_parallax = 0.05;      // de-rotated median displacement, share of the image width
  double max_interval_s = 2.0;     // a reference older than this is measured against anyway
  double hover_parallax_px = 1.0;  // below this for hover_s: zero velocity
  double hover_s = 1.0;
  int min_keypoints = 100;  // a frame with fewer never becomes a reference
  // The altimeter: a DVL's four Janus beams this far off the body's z axis,
  // at 45, 135, 225 and 315 degrees from the bow (its altitude is their mean
  // vertical range); 0: one vertical beam (an echo sounder).
  double altimeter_beam_deg = 30;
  TwoViewOptions two_view;
  void Check() const;
};

struct VoMeasurement {
  double time_s = 0;                       // of the frame that closed the interval
  double interval_s = 0;                   // from the reference frame
  Eigen::Vector3d body_velocity_mps;       // mean over the interval, body axes (x bow, y starboard, z down)
  Eigen::Matrix3d covariance;              // of the mean velocity
  MotionModel model = MotionModel::kNone;  // kNone: the zero-velocity measurement of a hovering vehicle
  int inliers = 0;
};

class VisualOdometry {
 public:
  // vo_sigma_mps: each measurement's noise per body axis (seed 003 Table 2 by default).
  VisualOdometry(const CameraModel& camera, const VoOptions& options, const Eigen::Vector3d& vo_sigma_mps);

  // The next frame (time order) with its navigation pose: attitude and
  // altitude are used, position is not. A measurement when this frame closes
  // a reference interval.
  std::optional<VoMeasurement> Add(const FrameFeatures& features, double time_s, const VehiclePose& nav);

  struct Counts {
    int frames = 0, measurements = 0, homography = 0, essential = 0, hover = 0;
    int failed_pairs = 0;      // both models failed: no measurement
    int low_texture = 0;       // frames with too few keypoints or matches
    int missing_altitude = 0;  // no usable altitude: no measurement
    int identical = 0;         // the same photo as the reference, bit for bit (a frozen camera): no measurement
    long motion_inliers = 0;   // summed over the homography and essential measurements (seed 004's Table 4)
  };
  const Counts& counts() const { return counts_; }
  const ModelSwitch& models() const { return models_; }
  // Forgets the reference frame: the next frame starts afresh (after a gap in time).
  void Restart() { reference_.reset(); }

 private:
  struct Reference {
    FrameFeatures features;
    cv::Mat descriptors;  // CV_32F, for the matcher
    double time_s = 0;
    VehiclePose nav;
  };
  bool TakeAsReference(const FrameFeatures& features, double time_s, const VehiclePose& nav);

  CameraModel camera_;
  VoOptions options_;
  Eigen::Vector3d vo_sigma_mps_;
  ModelSwitch models_;
  std::optional<Reference> reference_;
  Counts counts_;
};

}  // namespace seamap
