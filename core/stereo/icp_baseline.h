#pragma once
// The seed paper's comparison: the pose from registering point clouds with
// ICP instead of matching features. The model's points (object frame) are
// registered onto each pair's triangulated cloud (all stereo matches, as
// the paper's 252-point cloud) with OpenCV contrib's surface_matching ICP,
// seeded with 12 rotations about the viewing axis (its single-pose call
// always starts from identity), keeping the lowest residual.
#include <vector>

#include "core/stereo/object_locator.h"

namespace seamap {

struct IcpOptions {
  SiftOptions sift;
  StereoMatchOptions match;
  int iterations = 100;
  float tolerance = 0.005f;
  float rejection_scale = 2.5f;
  int levels = 3;
  int normal_neighbours = 10;
  int seeds = 12;
  double max_rms_m = 0.02;  // found: nearest-neighbour RMS
  double near_m = 0.03;     // and at least min_near points within this
  int min_near = 30;
};

struct IcpRegistration {
  Rigid object_from_camera = Rigid::Identity();
  double rms_m = 0;  // nearest-model-point RMS of the scene points within near_m
  int near = 0;      // scene points within near_m of a model point
};

// Registers model points (object frame) onto scene points (camera frame).
IcpRegistration RegisterIcp(const std::vector<Eigen::Vector3d>& model_object,
                            const std::vector<Eigen::Vector3d>& scene_camera, const IcpOptions& options);

// stereo-locate --method icp: each pair on its own; the result is the first pair's pose.
LocateResult LocateObjectIcp(const ObjectModel& model, const StereoCalibration& calibration,
                             const std::vector<LoadedPair>& pairs, const IcpOptions& options);

}  // namespace seamap
