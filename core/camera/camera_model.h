#pragma once
// Pinhole camera with OpenCV's Brown-Conrady distortion (k1,k2,p1,p2,k3) and
// its mounting on the vehicle. Default mounting: optical axis straight down,
// image top towards the vehicle's bow, image right towards starboard.
#include <array>
#include <string>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace seamap {

struct CameraModel {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<double, 5> distortion{};  // k1, k2, p1, p2, k3

  // Extra rotation of the camera relative to the default downward mounting,
  // degrees, applied as roll (about image y... see camera_model.cc), and the
  // camera's offset from the navigation reference point in the vehicle frame
  // (x forward, y starboard, z down), metres.
  Eigen::Vector3d mount_rpy_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d mount_offset_m = Eigen::Vector3d::Zero();

  cv::Matx33d K() const { return {fx, 0, cx, 0, fy, cy, 0, 0, 1}; }
  cv::Mat DistortionCoeffs() const;  // 1x5 CV_64F
  bool HasDistortion() const;

  // Rotation taking camera-frame vectors (OpenCV: x right, y down, z forward
  // along the optical axis) to the vehicle body frame (x fwd, y stbd, z down).
  Eigen::Matrix3d CameraToBody() const;

  // Throws InputError naming the parameter when a value is missing/invalid.
  void Validate(const std::string& source) const;
};

// Loads a camera from JSON (our format, see README) or an OpenCV calibration
// YAML/XML (camera_matrix, distortion_coefficients, image_width, image_height),
// chosen by extension. Throws InputError naming file and field.
CameraModel LoadCamera(const std::string& path);
void SaveCameraJson(const CameraModel& camera, const std::string& path);

// The seed paper's shortcut: focal length in mm and pixel pitch in micrometres,
// principal point at the image centre, no distortion.
CameraModel CameraFromFocalLength(double focal_mm, double pixel_pitch_um, int width, int height);

}  // namespace seamap
