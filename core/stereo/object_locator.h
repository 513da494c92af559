#pragma once
// `seamap stereo-locate`: the pose of the vehicle's stereo camera in the
// object's frame from one or several pairs. Each pair is registered against
// the model alone (core/stereo/model_registration) and judged by the found
// rule; the accepted pairs are then solved jointly: the pose of every pair,
// the matched model points under their priors, and tie points (SIFT points
// matched between the pairs, object and seabed) whose 3D positions are free.
// The result is the first accepted pair's object_from_camera with its
// covariance, or found = false with the reason: never a confident wrong pose.
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/stereo/model_registration.h"
#include "core/stereo/object_model.h"
#include "core/stereo/stereo_pairs.h"

namespace seamap {

// What the vehicle measured of the rig's path (motion.json): the left camera's
// pose per pair in any fixed frame, and how well each relative pose is known.
struct RigMotion {
  std::map<std::string, Rigid> world_from_camera;  // by pair name
  double sigma_m = 0.002, sigma_deg = 0.02;        // per axis, of each pair's pose (independent errors)
};

// Reads motion.json: {"world_from_camera": {pair: 4x4}, "sigma_m": s, "sigma_deg": s};
// throws InputError naming the file and field.
RigMotion ReadRigMotion(const std::string& path);

struct LocateOptions {
  SiftOptions sift;
  StereoMatchOptions match;
  ModelRegistrationOptions registration;
  int min_inliers = 12;
  double min_inlier_share = 0.25;  // of the pair's model matches
  double max_rms_px = 1.5;
  double min_hull_share = 0.02;     // of the image area
  double min_spread_m = 0.05;       // second singular value of the inlier cloud
  double max_point_sigma_m = 0.02;  // the model's points in the camera (PointSigmaM)
  bool tie_points = true;           // with several pairs
  int min_tie_points = 10;          // a later pair tied to the others by fewer stays out of the joint
  // The rig's own motion (--motion): each pair's world_from_camera from the
  // vehicle's navigation; the joint solution holds the pairs to it.
  RigMotion motion;
  void Check() const;
};

struct PairResult {
  std::string pair;
  bool accepted = false;
  bool joined = false;                                  // failed only the spread test alone, solved with accepted pairs
  std::string reason;                                   // when not accepted
  Rigid single_object_from_camera = Rigid::Identity();  // this pair alone
  Rigid object_from_camera = Rigid::Identity();         // the joint solution
  int matches = 0, inliers = 0, model_views_matched = 0, stereo_points = 0;
  double reprojection_rms_px = 0;
  double features_s = 0, registration_s = 0;
};

struct LocateResult {
  bool found = false;
  std::string reason;
  std::string method = "features";
  Rigid object_from_camera = Rigid::Identity();  // the first accepted pair
  std::vector<PairResult> pairs;                 // every pair tried, in order
  int tie_points = 0;
  double joint_rms_px = 0;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Vector3d position_sigma_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_sigma_deg = Eigen::Vector3d::Zero();
  double point_sigma_m = 0;  // RMS over the model's points, in the camera frame
  double features_s = 0, registration_s = 0, joint_s = 0;
};

// Epipolar failures (a pair that is not a pair for this calibration) throw
// InputError naming the pair; everything else ends in the result.
LocateResult LocateObject(const ObjectModel& model, const StereoCalibration& calibration,
                          const std::vector<LoadedPair>& pairs, const LocateOptions& options);

// The found rule's tests on one registered pair: empty when accepted, else the failing test.
std::string JudgePair(const Registration& reg, const StereoFrame& frame, const ObjectModel& model, cv::Size image_size,
                      const LocateOptions& options);

nlohmann::json LocateResultToJson(const LocateResult& result, const std::string& model_name);

}  // namespace seamap
