#pragma once
// A frame's features for registration: CLAHE, then SIFT keypoints with 8-bit
// descriptors (a quarter of the memory of float ones: 720 frames x 2000
// features is 184 MB), detected at a working size whose longest side is at
// most `max_side_px` (a 4000x2600 ROV still is searched at 1600x1040), and
// returned in ideal (undistorted) full-resolution pixels, so every later
// step works in the camera model's own pinhole coordinates.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/enhance/enhance_chain.h"

namespace seamap {

struct FeatureOptions {
  int max_features = 2000;
  int max_side_px = 1600;            // working size: longest side at most this
  double clahe_clip = 2.0;           // CLAHE clip limit (8x8 tiles)
  double contrast_threshold = 0.04;  // SIFT's; a frame with too few keypoints is retried at half of it
  int min_keypoints = 100;           // below this, retry with a relaxed detector and CLAHE clip 4
  // OpenCV's SIFT doubles its input before the first octave. Given half the
  // working size, its first octave is the working size itself: 2.3x faster
  // (85 against 190 ms on a 696x520 frame), and the finest scale it drops is
  // below a working pixel, mostly noise (docs/TRAJECTORIES.md measures both).
  bool skip_upsampled_octave = true;
  // Applied to the frame before anything else (feature_enhancement.h); empty: none.
  EnhanceChain enhance;
  void Check() const;  // InputError naming the option
};

struct FrameFeatures {
  std::vector<cv::Point2f> ideal_px;  // keypoints, ideal pixels at full resolution
  cv::Mat descriptors;                // one CV_8U row of 128 per keypoint
  bool relaxed = false;               // the relaxed detector was needed
  size_t Bytes() const { return ideal_px.size() * sizeof(cv::Point2f) + descriptors.total(); }
};

// Why a decoded frame cannot give features, before any are looked for, or
// nullopt: "no texture" when it is uniform (all black, all white: under 1
// grey level of standard deviation), where CLAHE would only amplify noise.
std::optional<std::string> WhyNoTexture(const cv::Mat& image);

// Whether two frames' features are the same, point for point and bit for
// bit: a camera that froze and repeats its last photo (no real camera
// takes the same photo twice: its sensor's noise differs).
bool SameFeatures(const FrameFeatures& a, const FrameFeatures& b);

// The working scale for a camera (1 or less).
double WorkingScale(const CameraModel& camera, int max_side_px);

// image: 8- or 16-bit gray or colour, of the camera's size (any other size
// with the same aspect ratio is scaled to it).
FrameFeatures DetectFeatures(const cv::Mat& image, const CameraModel& camera, const FeatureOptions& options);

}  // namespace seamap
