#pragma once
// How well a fitted similarity is known, from the normal equations: each good
// keyframe brings information 1 / sigma^2 per axis times the number of GPS
// fixes it stands for (horizontal) and the depth's (vertical). Also the shape
// test for a line of keyframes.
#include <vector>

#include <Eigen/Core>

#include "core/georef/similarity.h"

namespace seamap {

struct FitUncertainty {
  bool ok = false;
  Eigen::Vector3d rotation_sigma_deg = Eigen::Vector3d::Zero();  // about east, north, up
  double scale_sigma = 0;                                        // relative (0.01 = 1 %)
  Eigen::Vector3d position_sigma_m = Eigen::Vector3d::Zero();    // at the good keyframes' centroid
  // Parameters: rotation about east, north, up (rad), log scale, translation at the centroid.
  Eigen::Matrix<double, 7, 7> covariance = Eigen::Matrix<double, 7, 7>::Zero();
  Eigen::Vector3d centroid_slam = Eigen::Vector3d::Zero();

  // Predicted horizontal error (2D RMS, metres) of a SLAM point mapped by the fit.
  double HorizontalSigma(const Similarity& fit, const Eigen::Vector3d& slam) const;
};

// horizontal_information[i], vertical_information[i]: 1 / sigma^2 per axis
// (metres^-2) of good keyframe i's target.
FitUncertainty PredictUncertainty(const Similarity& fit, const std::vector<Eigen::Vector3d>& slam,
                                  const std::vector<double>& horizontal_information,
                                  const std::vector<double>& vertical_information);

// sqrt(l2 / l1) of the weighted, centred covariance of the points
// (l1 >= l2 >= l3): 0 for points on one line, 1 for a round cloud.
double EigenRatio(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights);

}  // namespace seamap
