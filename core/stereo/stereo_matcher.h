#pragma once
// One stereo pair as points in its left camera frame: SIFT in both images,
// keypoints rectified, left/right matches along rectified rows (ratio test,
// mutual best, disparity within a depth range), triangulated with their
// covariance. Before that, the epipolar check that tells a pair taken with
// another rig (or swapped images) from a good one.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/stereo/sift_features.h"
#include "core/stereo/stereo_calibration.h"

namespace seamap {

struct StereoMatchOptions {
  double ratio = 0.8;        // Lowe's ratio test
  double max_row_px = 1.5;   // rectified rows of a match differ by at most this
  double min_depth_m = 0.5;  // disparity range from the depth range
  double max_depth_m = 20;
  double sigma_floor_px = 0.05;  // keypoint noise is never taken as lower than this
};

struct StereoPoint {
  int left = -1, right = -1;  // keypoint indices
  Eigen::Vector3d xyz;        // left camera frame, metres
  Eigen::Matrix3d cov;        // its covariance, m^2
};

// What unconstrained ratio-test matches say about the pair and the calibration.
struct EpipolarCheck {
  int matches = 0;
  double median_row_px = 0;      // median |rectified row difference|
  double row_ok_fraction = 0;    // share of matches on the same rectified row (within 2 px)
  double positive_fraction = 0;  // share of positive disparities among those
  // Judged on the matches that agree in row: on a hazy, plain pair most unconstrained
  // matches are wrong and their median row says nothing; with the wrong calibration
  // (or another camera's images) almost none agree.
  bool Passes() const { return matches < 20 || (row_ok_fraction >= 0.3 && positive_fraction >= 0.8); }
  std::string Describe() const;  // why it fails
};

struct StereoFrame {
  std::string name;
  ImageFeatures left, right;
  std::vector<StereoPoint> points;
  std::vector<int> point_of_left;  // per left keypoint: its point, or -1
  double sigma_px = 0;             // keypoint noise, from the rows of the matches
  EpipolarCheck epipolar;
  double seconds = 0;  // detection, matching, triangulation
};

EpipolarCheck CheckEpipolar(const ImageFeatures& left, const ImageFeatures& right, double ratio);

// Matches rectified keypoints along rows; returns (left, right) index pairs.
std::vector<std::pair<int, int>> MatchAlongRows(const ImageFeatures& left, const ImageFeatures& right,
                                                const RectifiedRig& rig, const StereoMatchOptions& options);

// Keypoint noise from the row differences of matches (pure noise for a good
// calibration): a robust spread / sqrt(2).
double KeypointSigmaFromRows(const ImageFeatures& left, const ImageFeatures& right,
                             const std::vector<std::pair<int, int>>& matches);

// Detection, rectification, epipolar check (InputError naming the pair when
// it fails), matching and triangulation.
StereoFrame MakeStereoFrame(const std::string& name, const cv::Mat& left, const cv::Mat& right,
                            const StereoCalibration& calibration, const SiftOptions& sift,
                            const StereoMatchOptions& options);

}  // namespace seamap
