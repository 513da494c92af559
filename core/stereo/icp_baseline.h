#pragma once
// The seed paper's comparison: the pose from registering point clouds with
// ICP instead of matching features. The model's points (object frame) are
// registered onto each pair's triangulated cloud (all stereo matches, as
// the paper's 252-point cloud) with OpenCV contrib's surface_matching ICP,
// seeded with 12 rotations about the viewing axis (its single-pose call
// always starts from identity), keeping the seed that brings the most scene
// points near the model. Both clouds are mostly seabed, and a flat seabed
// slides along itself with nearly every point still "near": so the points of
// the dominant plane are set aside, ICP registers the structure standing off
// it, and the found rule asks that structure to agree.
#include <string>
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
  double plane_m = 0.04;      // a point within this of the dominant plane is seabed
  double off_plane_m = 0.08;  // structure: points further than this from it
  double max_rms_m = 0.02;    // found: nearest-neighbour RMS
  double near_m = 0.03;       // and at least min_near structure points within this
  int min_near = 30;
  double min_near_fraction = 0.3;  // of the scene's structure points
};

// The points further than off_plane_m from the plane that holds the most points
// within plane_m (RANSAC); all of them when no plane holds a third of the cloud.
std::vector<Eigen::Vector3d> OffDominantPlane(const std::vector<Eigen::Vector3d>& points, double plane_m,
                                              double off_plane_m);

struct IcpRegistration {
  Rigid object_from_camera = Rigid::Identity();
  double rms_m = 0;   // nearest-model-point RMS of the structure points within near_m
  int near = 0;       // scene structure points within near_m of a model point
  int structure = 0;  // scene points off the dominant plane
};

// Registers model points (object frame) onto scene points (camera frame), both
// without their dominant plane.
IcpRegistration RegisterIcp(const std::vector<Eigen::Vector3d>& model_all,
                            const std::vector<Eigen::Vector3d>& scene_all, const IcpOptions& options);

// Found: enough of the scene's structure lies on the model. A reason when not.
bool IcpFound(const IcpRegistration& registration, const IcpOptions& options, std::string* reason);

// stereo-locate --method icp: each pair on its own; the result is the first pair's pose.
LocateResult LocateObjectIcp(const ObjectModel& model, const StereoCalibration& calibration,
                             const std::vector<LoadedPair>& pairs, const IcpOptions& options);

}  // namespace seamap
