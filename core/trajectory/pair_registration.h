#pragma once
// Registers two overlapping frames on the seabed: the 2D rigid motion
// (dt, dpsi) with a_i(p) = dt + Rot(dpsi) a_j(q) for every matched pair of
// keypoints p of frame i and q of frame j (ground_offsets.h), its covariance,
// and whether to trust it. Matching is guided by the navigation: a first
// unguided pass on the strongest keypoints of j (Lowe ratio) and a 2D rigid
// RANSAC find the motion roughly, whatever the navigation's drift; then
// every keypoint of j is looked for near where that motion puts it in i.
// On relief (options.parallax_share > 0) points off the mean plane move
// between views by up to parallax_share x the baseline: the search is
// widened by that much and the inliers are those consistent with one
// relative camera motion (essential matrix, RANSAC in ideal pixels) instead
// of one rigid motion of the ground plane. The rigid motion fitted to them
// is then only the bundle adjustment's starting point.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/trajectory/frame_features.h"

namespace seamap {

struct RegistrationOptions {
  double ratio = 0.8;           // Lowe's ratio test
  double inlier_ground_px = 3;  // RANSAC threshold, in ground pixels
  int min_inliers = 20;
  double min_inlier_share = 0.25;  // of the guided matches
  double min_spread = 0.05;        // inliers' hull over the footprint's area
  double gate = 11.34;             // Mahalanobis distance^2 to the navigation's prediction (3 dof, 1 %)
  int seed_keypoints = 400;        // of frame j, in the unguided pass
  int ransac_iterations = 400;
  double parallax_share = 0;  // relief up to this share of the altitude; 0: a flat seabed (planar inliers)
  double epipolar_px = 1.0;   // essential-matrix RANSAC threshold, ideal pixels (parallax_share > 0)
  void Check() const;
};

// A frame as registration sees it.
struct RegistrationFrame {
  const FrameFeatures* features = nullptr;
  std::vector<cv::Point2d> offsets;    // ground offsets of its keypoints (heading-free, metres)
  cv::Point2d position_m;              // navigation (east, north)
  double heading_rad = 0;              // navigation
  double ground_px_m = 0.003;          // ground sample distance
  double footprint_m2 = 1;             // footprint area
  cv::Matx33d k = cv::Matx33d::eye();  // the camera's pinhole matrix (ideal pixels), for the essential matrix
};

// How far the navigation's relative pose of two frames may be off (1 sigma).
struct RelativeNavNoise {
  double position_m = 0.01;
  double heading_rad = 0.01;
};

// Not "Registration": core/stereo has one, and one program cannot hold two of a name.
struct PairRegistration {
  bool accepted = false;
  std::string reason;  // why not, when not
  double dt_east_m = 0, dt_north_m = 0, dheading_rad = 0;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  // of (dt_east, dt_north, dheading)
  int matches = 0, inliers = 0;
  double rms_m = 0;                                 // inliers' residual RMS
  std::vector<std::pair<int, int>> inlier_matches;  // (keypoint of i, keypoint of j), when accepted
};

PairRegistration RegisterPair(const RegistrationFrame& i, const RegistrationFrame& j, const RelativeNavNoise& noise,
                              const RegistrationOptions& options, uint64_t seed);

// The rigid motion (dt, dpsi) best mapping q onto p in least squares (a_p = dt + Rot(dpsi) a_q).
struct Rigid2D {
  cv::Point2d dt;
  double dpsi = 0;
};
Rigid2D FitRigid(const std::vector<cv::Point2d>& p, const std::vector<cv::Point2d>& q);

}  // namespace seamap
