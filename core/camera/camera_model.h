#pragma once
// Pinhole camera with OpenCV's Brown-Conrady distortion (k1,k2,p1,p2,k3) and
// its mounting on the vehicle.
//
// Frames:
//  - camera (OpenCV): x = image right, y = image down, z = optical axis.
//  - body: x forward (bow), y starboard, z down.
// Default mounting: optical axis straight down, image top towards the bow,
// image right towards starboard (camera x -> body +y, camera y -> body -x,
// camera z -> body +z).
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace seamap {

// The largest image side a camera model may have (pixels): sensors are a few
// thousand; beyond this a width is a typo.
constexpr int kMaxImageSide = 100000;

struct CameraModel {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels; pixel centres at integers
  std::array<double, 5> distortion{};     // k1, k2, p1, p2, k3

  // Extra rotation of the camera relative to the default downward mounting,
  // degrees, as (roll, pitch, yaw) about the BODY axes (x fwd, y stbd, z down):
  // R_mount = Rz(yaw) * Ry(pitch) * Rx(roll), so pitch +10 tilts the optical
  // axis forward, roll +10 tilts it towards port, yaw +90 turns image right
  // towards aft. And the camera's offset from the navigation reference point
  // in the body frame (x forward, y starboard, z down), metres.
  Eigen::Vector3d mount_rpy_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d mount_offset_m = Eigen::Vector3d::Zero();

  cv::Matx33d K() const { return {fx, 0, cx, 0, fy, cy, 0, 0, 1}; }
  cv::Mat DistortionCoeffs() const;  // 1x5 CV_64F
  bool HasDistortion() const;

  // Rotation taking camera-frame vectors to the vehicle body frame:
  // R_mount * R_default (see above).
  Eigen::Matrix3d BodyFromCamera() const;

  // Raw (distorted) pixels to ideal pinhole pixels and back (same K).
  std::vector<cv::Point2d> Undistort(const std::vector<cv::Point2d>& raw) const;
  std::vector<cv::Point2d> Distort(const std::vector<cv::Point2d>& ideal) const;

  // Throws InputError(source, 0, field, ...) naming the first invalid
  // parameter: sides 1..kMaxImageSide; focal lengths finite, at most 1e7 px
  // and giving a field of view under 170 degrees; the principal point inside
  // the image; distortion that moves the image corners by less than ten
  // image diagonals; a mounting offset within 100 m.
  void Validate(const std::string& source) const;
};

// Loads a camera, chosen by extension:
//  .json: {"width", "height", "fx", "fy", "cx", "cy",
//          "distortion": [k1, k2, p1, p2, k3] (optional; 0-5, 8, 12 or 14 values,
//                        coefficients past k3 must be zero),
//          "mount": {"roll_deg", "pitch_deg", "yaw_deg", "offset_m": [x, y, z]} (optional)}
//         or the seed shortcut {"width", "height", "focal_mm", "pixel_pitch_um"}
//         (optional "cx", "cy", "distortion", "mount").
//  .yaml/.yml/.xml: OpenCV calibration (camera_matrix, distortion_coefficients,
//         image_width, image_height), as written by cv::FileStorage or ROS.
// Throws InputError naming file and field.
CameraModel LoadCamera(const std::string& path);
void SaveCameraJson(const CameraModel& camera, const std::string& path);

// The seed paper's shortcut: focal length in mm and pixel pitch in micrometres,
// principal point at the image centre (w/2 - 0.5, h/2 - 0.5), no distortion.
CameraModel CameraFromFocalLength(double focal_mm, double pixel_pitch_um, int width, int height);

}  // namespace seamap
