#pragma once
// Where a located object is on the Earth: the stereo pose (object_from_camera
// of the left camera) carried through the rig's mounting on the vehicle and
// the vehicle's navigation pose into latitude, longitude, depth and heading.
#include <string>

#include <Eigen/Core>

#include "core/camera/vehicle_pose.h"
#include "core/geo/local_frame.h"
#include "core/geo/rotation.h"
#include "core/stereo/rigid_transform.h"

namespace seamap {

// The stereo rig on the vehicle: which way its left camera looks and where it
// sits in the body frame (x forward, y starboard, z down; metres).
// The left camera's rotation into the body frame is BodyFromCamera(looking)
// (core/geo/rotation.h).
struct RigMount {
  using Looking = CameraLooking;
  Looking looking = Looking::kForward;  // kDown: image top towards the bow
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();
};

// "forward" or "down"; InputError naming `option` otherwise.
RigMount::Looking ParseLooking(const std::string& text, const std::string& option);

struct PlacedObject {
  LatLon position;         // the object frame's origin
  LocalXY local;           // the same, east/north in the navigation's local frame
  double depth_m = 0;      // below the surface (the vehicle's depth + how far below it)
  double heading_deg = 0;  // the object's x axis on the horizontal, clockwise from true north, [0, 360)
};

// `vehicle`: the navigation's pose when the pair was taken, in `frame`.
PlacedObject PlaceObject(const Rigid& object_from_camera, const RigMount& mount, const VehiclePose& vehicle,
                         const LocalFrame& frame);

}  // namespace seamap
