#pragma once
// A calibrated stereo rig as cv::stereoCalibrate gives it (K1, D1, K2, D2,
// R, T with p_right = R p_left + T) and its rectified geometry, computed by
// cv::stereoRectify (R1, R2, P1, P2 stored in a file are ignored). Keypoints
// are undistorted and rectified as points; images are never remapped.
//
// Rectified frames: both cameras rotated to be parallel (left: R1, right:
// R2), rows equal, the right camera `baseline_m` along +x of the left one.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace seamap {

struct RectifiedRig {
  double f = 0, cx = 0, cy = 0;  // pixels, the same for both rectified cameras
  double baseline_m = 0;
  Eigen::Matrix3d rect_from_left = Eigen::Matrix3d::Identity();  // R1

  // Rectified pixels of a point in the left camera frame; false behind the camera.
  bool Project(const Eigen::Vector3d& left_xyz, cv::Point2d* left_px, cv::Point2d* right_px) const;
  // The point in the left camera frame from rectified left/right pixels
  // (Z = f B / d along the rectified axis, then R1^T back to the left camera).
  Eigen::Vector3d Triangulate(const cv::Point2d& left_px, const cv::Point2d& right_px) const;
  // Its covariance for keypoint noise sigma_px in each image (rows and columns).
  Eigen::Matrix3d TriangulationCovariance(const cv::Point2d& left_px, const cv::Point2d& right_px,
                                          double sigma_px) const;
};

struct StereoCalibration {
  cv::Size image_size;
  cv::Matx33d K1, K2;
  std::vector<double> D1, D2;  // OpenCV order k1, k2, p1, p2[, k3, ...]
  cv::Matx33d R = cv::Matx33d::eye();
  cv::Vec3d T;
  // Derived by Rectify().
  cv::Matx33d R1, R2;
  cv::Matx34d P1, P2;
  RectifiedRig rig;

  // Throws InputError(source, 0, key, ...) for implausible values: focal
  // lengths <= 0, |T| outside 0.02-2 m, R more than 20 deg from identity.
  void Check(const std::string& source) const;
  void Rectify();

  // Raw (distorted) pixels -> rectified pixels.
  std::vector<cv::Point2d> RectifyLeft(const std::vector<cv::Point2d>& raw_px) const;
  std::vector<cv::Point2d> RectifyRight(const std::vector<cv::Point2d>& raw_px) const;
  // Raw pixels of a point in the left camera frame, in the left (right = false) or right image.
  cv::Point2d ProjectRaw(const Eigen::Vector3d& left_xyz, bool right) const;
  // The right camera's pose in the left camera frame (left_from_right).
  Eigen::Matrix4d LeftFromRight() const;
};

// Reads a cv::FileStorage YAML/XML with K1, D1, K2, D2, R, T and
// image_width/image_height (or image_size: [w, h]); checks and rectifies.
// Throws InputError naming file and key.
StereoCalibration LoadStereoCalibration(const std::string& path);
void SaveStereoCalibration(const StereoCalibration& calibration, const std::string& path);

}  // namespace seamap
