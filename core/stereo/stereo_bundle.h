#pragma once
// The least-squares problem behind both commands: camera poses
// (object_from_camera of each pair's left camera) and 3D points in the object
// frame, observed as rectified pixels in the left and right images of the
// pairs. Residuals are stereo reprojection errors divided by the keypoint
// noise (Huber beyond 2 sigma); a point may carry a prior (its position and
// covariance from the model), whitened by that covariance. Depth noise is
// ~Z/B = 14x the lateral noise at 3.6 m, which is why 3D distances are never
// minimised directly.
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/stereo/rigid_transform.h"
#include "core/stereo/stereo_calibration.h"

namespace seamap {

struct BundleObservation {
  int pose = -1, point = -1;
  cv::Point2d left_px, right_px;  // rectified
  bool has_right = true;
};

struct BundlePoint {
  Eigen::Vector3d xyz;     // object frame (updated)
  bool has_prior = false;  // prior on xyz: prior_xyz with prior_cov
  // Zero without a prior, so copying such a point reads no unset values.
  Eigen::Vector3d prior_xyz = Eigen::Vector3d::Zero();
  Eigen::Matrix3d prior_cov = Eigen::Matrix3d::Zero();
  bool fixed = false;
};

// The vehicle's own measure of how the rig moved between two pairs (its
// navigation: DVL and INS), as a prior on their relative pose.
struct BundleMotion {
  int from_pose = -1, to_pose = -1;
  Rigid from_camera_from_to_camera = Rigid::Identity();
  double sigma_m = 0.002, sigma_rad = 0.0003;  // per axis
};

struct BundleProblem {
  std::vector<Rigid> poses;  // object_from_camera (updated)
  std::vector<bool> pose_fixed;
  std::vector<BundlePoint> points;
  std::vector<BundleObservation> observations;
  std::vector<BundleMotion> motions;
  double sigma_px = 0.3;
};

struct BundleResult {
  double rms_px = 0;       // image residuals, unweighted
  double sigma_scale = 1;  // sqrt(2 cost / (m - p)), noise units
  int iterations = 0;
  bool converged = false;
  // Of pose 0 when asked: rotation vector [rad] then translation [m], scaled by sigma_scale^2.
  bool has_covariance = false;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  std::vector<double> residual_px;  // per observation: max of its left and right errors
};

// Solves in place. covariance_of_pose: the index of a free pose whose 6x6
// covariance is wanted, or -1.
BundleResult SolveBundle(BundleProblem* problem, const RectifiedRig& rig, int covariance_of_pose = -1,
                         int max_iterations = 50);

// Projection of an object-frame point into a pair at object_from_camera: rectified left and right pixels.
bool ProjectToPair(const RectifiedRig& rig, const Rigid& object_from_camera, const Eigen::Vector3d& xyz_object,
                   cv::Point2d* left_px, cv::Point2d* right_px);

}  // namespace seamap
