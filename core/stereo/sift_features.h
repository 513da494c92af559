#pragma once
// SIFT keypoints with 8-bit descriptors at sub-pixel positions that mean what
// they say. OpenCV 4.6's SIFT doubles the image (bilinear, pixel centres at
// integers) before its first octave and reports positions as the doubled
// image's coordinates halved: every keypoint lands +0.25 px right of and
// below the feature (docs/STEREO.md measures it; MeasureSiftOffsetPx does it
// on any image). Left in, that constant costs about 2 mm at 3.6 m.
#include <vector>

#include <opencv2/core.hpp>

#include "core/enhance/enhance_chain.h"

namespace seamap {

// The offset of OpenCV 4.6's SIFT keypoints in x and y, pixels (subtracted).
constexpr double kSiftOffsetPx = 0.25;

struct SiftOptions {
  int max_features = 4000;
  double contrast_threshold = 0.02;  // low: the sea's contrast is low
  double offset_px = kSiftOffsetPx;  // subtracted from x and y (0 leaves OpenCV's positions)
  double clahe_clip = 0;             // > 0: CLAHE (8x8 tiles) before detection, for haze
  EnhanceChain enhance;              // seed 004's chain before detection (--feature-enhance); empty: none
  void Check() const;                // InputError naming the option
};

struct ImageFeatures {
  std::vector<cv::Point2d> raw_px;   // corrected positions in the raw (distorted) image
  std::vector<cv::Point2d> rect_px;  // the same, undistorted and rectified (filled by the caller)
  std::vector<float> size_px;        // keypoint diameter
  cv::Mat descriptors;               // one CV_8U row of 128 per keypoint
  size_t size() const { return raw_px.size(); }
};

// 8- or 16-bit gray or colour image. Keypoints strongest first. Positions are
// the raw image's: the chain changes pixel values, not geometry.
ImageFeatures DetectSift(const cv::Mat& image, const SiftOptions& options);

// The constant offset (x, y) of SIFT keypoints in `image`, pixels, found
// without ground truth: a feature at x is detected at x + b in the image and,
// mapped back, at x - b in its mirror image, so b is half the median
// difference. Uses options.offset_px = 0 internally.
cv::Point2d MeasureSiftOffsetPx(const cv::Mat& image, SiftOptions options);

}  // namespace seamap
