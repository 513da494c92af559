#include "core/stereo/object_georef.h"

#include <cmath>

#include "core/camera/frame_projector.h"
#include "core/util/error.h"

namespace seamap {

Eigen::Matrix3d BodyFromRigCamera(RigMount::Looking looking) {
  Eigen::Matrix3d body_from_camera;
  if (looking == RigMount::Looking::kForward) {
    // camera x (right) -> starboard, y (down) -> down, z (view) -> forward
    body_from_camera << 0, 0, 1,  //
        1, 0, 0,                  //
        0, 1, 0;
  } else {
    // camera x (right) -> starboard, y (image down) -> aft, z (view) -> down
    body_from_camera << 0, -1, 0,  //
        1, 0, 0,                   //
        0, 0, 1;
  }
  return body_from_camera;
}

RigMount::Looking ParseLooking(const std::string& text, const std::string& option) {
  if (text == "forward") return RigMount::Looking::kForward;
  if (text == "down") return RigMount::Looking::kDown;
  throw InputError("", 0, option, "expected forward or down, got '" + text + "'");
}

PlacedObject PlaceObject(const Rigid& object_from_camera, const RigMount& mount, const VehiclePose& vehicle,
                         const LocalFrame& frame) {
  const Rigid camera_from_object = object_from_camera.inverse();
  const Eigen::Matrix3d ned_from_body = NedFromBody(vehicle);
  const Eigen::Matrix3d ned_from_camera = ned_from_body * BodyFromRigCamera(mount.looking);
  // The object's origin relative to the vehicle's navigation point, north/east/down.
  const Eigen::Vector3d ned = ned_from_body * mount.offset_m + ned_from_camera * camera_from_object.translation();
  PlacedObject placed;
  placed.local = {vehicle.east_m + ned.y(), vehicle.north_m + ned.x()};
  placed.position = frame.ToLatLon(placed.local);
  placed.depth_m = vehicle.depth_m + ned.z();
  const Eigen::Vector3d x_axis = ned_from_camera * camera_from_object.linear().col(0);
  const double heading = std::atan2(x_axis.y(), x_axis.x()) * 180 / M_PI;
  placed.heading_deg = std::fmod(heading + 360.0, 360.0);
  return placed;
}

}  // namespace seamap
