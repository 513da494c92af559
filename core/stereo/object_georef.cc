#include "core/stereo/object_georef.h"

#include <cmath>

#include "core/camera/frame_projector.h"
#include "core/util/error.h"

namespace seamap {

RigMount::Looking ParseLooking(const std::string& text, const std::string& option) {
  if (text == "forward") return RigMount::Looking::kForward;
  if (text == "down") return RigMount::Looking::kDown;
  throw InputError("", 0, option, "expected forward or down, got '" + text + "'");
}

PlacedObject PlaceObject(const Rigid& object_from_camera, const RigMount& mount, const VehiclePose& vehicle,
                         const LocalFrame& frame) {
  const Rigid camera_from_object = object_from_camera.inverse();
  const Eigen::Matrix3d ned_from_body = NedFromBody(vehicle);
  const Eigen::Matrix3d ned_from_camera = ned_from_body * BodyFromCamera(mount.looking);
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
