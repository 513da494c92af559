#pragma once
// The object model of `seamap stereo-model` (object.json): 3D points in the
// object's frame, each with its covariance and, per overview view that saw
// it, its raw left pixel and SIFT descriptor. The frame is the left camera of
// the first overview pair (x right, y down, z forward, metres).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/stereo/rigid_transform.h"
#include "core/stereo/stereo_calibration.h"
#include "core/stereo/stereo_matcher.h"
#include "core/stereo/stereo_pairs.h"

namespace seamap {

struct ModelObservation {
  int view = 0;
  cv::Point2d raw_px;  // left image of that view
  cv::Mat descriptor;  // 1x128 CV_8U
};

struct ModelPoint {
  Eigen::Vector3d xyz;
  Eigen::Matrix3d cov;
  std::vector<ModelObservation> observations;
};

struct ObjectModel {
  std::string name;
  std::string frame = "first-overview-left-camera";
  double fx_px = 0, baseline_m = 0;
  cv::Size image_size;
  std::vector<std::pair<std::string, Rigid>> views;  // overview pair, object_from_camera
  std::vector<ModelPoint> points;
  // For matching: every observation's descriptor and the point it belongs to.
  cv::Mat descriptors;
  std::vector<int> descriptor_point;
  void IndexDescriptors();
};

struct ModelBuildOptions {
  SiftOptions sift;
  StereoMatchOptions match;
  double ratio = 0.8;
  double inlier_px = 2;
  int min_inliers = 12;
  bool bundle = true;  // bundle adjustment over the overview pairs
  void Check() const;
};

struct ModelBuildReport {
  int pairs = 0;
  std::vector<std::string> lines;  // one per pair: points, matches, inliers
  double bundle_rms_px = 0;
  double seconds = 0;
};

// Pair 1 defines the frame; each later pair is registered against the
// points built so far (InputError naming it when it does not overlap),
// observations of the same point are fused and a bundle adjustment (pair 1
// fixed) tightens poses and points.
ObjectModel BuildObjectModel(const std::vector<LoadedPair>& pairs, const StereoCalibration& calibration,
                             const std::string& name, const ModelBuildOptions& options, ModelBuildReport* report);

nlohmann::json ModelToJson(const ObjectModel& model);
// Throws InputError(path, 0, key, ...) for a malformed model.
ObjectModel ModelFromJson(const nlohmann::json& json, const std::string& path);
ObjectModel LoadObjectModel(const std::string& path);

}  // namespace seamap
