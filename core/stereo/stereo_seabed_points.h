#pragma once
// Stereo pairs as seabed points for the height model (issue 29: "where a
// stereo rig is given, its pairs"): each pair's triangulated points
// (stereo_matcher.h), carried through the rig's mounting and the vehicle's
// pose into the mission's local frame, metres up (height_grid.h's datum),
// beside the monocular tracks' points (core/terrain/seabed_point.h). One pair
// sees the seabed's shape at once, without relying on the vehicle's motion.
#include <Eigen/Core>

#include "core/camera/vehicle_pose.h"
#include "core/stereo/object_georef.h"
#include "core/stereo/stereo_matcher.h"
#include "core/terrain/seabed_point.h"

namespace seamap {

struct StereoSeabedOptions {
  // A point whose height is less certain than this is left out: far ranges
  // and short disparities, where a rig's 0.1 px is centimetres.
  double max_sigma_up_m = 0.02;
  // A point further than this from the plane at the navigation's altitude
  // (-(depth_m + altitude_m)) is left out, as build --terrain's tracks
  // (--max-relief): mismatches near the rig, fish, the top of a structure.
  double max_relief_m = 1.5;
  int max_points_per_pair = 3000;  // the strongest left keypoints first
  void Check() const;              // InputError naming the option
};

// The pair's points (left camera frame) as seabed points: east, north, up
// (-(depth_m + how far below the vehicle)), sigma_up_m from the
// triangulation's covariance (the pose's own error not included), views 2.
// Without an altitude (0) the relief bound is not applied.
SeabedPoints StereoSeabedPoints(const StereoFrame& frame, const RigMount& mount, const VehiclePose& vehicle,
                                const StereoSeabedOptions& options);

}  // namespace seamap
