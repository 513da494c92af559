#include "core/stereo/stereo_seabed_points.h"

#include <algorithm>
#include <cmath>

#include "core/camera/frame_projector.h"
#include "core/geo/rotation.h"
#include "core/util/error.h"

namespace seamap {

void StereoSeabedOptions::Check() const {
  if (!(max_sigma_up_m > 0)) throw InputError("", 0, "--max-sigma-up", "expected a height sigma > 0 (metres)");
  if (!(max_relief_m > 0)) throw InputError("", 0, "--max-relief", "expected metres > 0");
  if (max_points_per_pair < 1) throw InputError("", 0, "--max-points", "expected at least 1 point per pair");
}

SeabedPoints StereoSeabedPoints(const StereoFrame& frame, const RigMount& mount, const VehiclePose& vehicle,
                                const StereoSeabedOptions& options) {
  options.Check();
  const Eigen::Matrix3d ned_from_body = NedFromBody(vehicle);
  const Eigen::Matrix3d ned_from_camera = ned_from_body * BodyFromCamera(mount.looking);
  const Eigen::Vector3d rig_ned = ned_from_body * mount.offset_m;
  // Points in the order of their left keypoints (strongest first).
  std::vector<const StereoPoint*> order;
  for (const StereoPoint& p : frame.points) order.push_back(&p);
  std::sort(order.begin(), order.end(), [](const StereoPoint* a, const StereoPoint* b) { return a->left < b->left; });
  SeabedPoints out;
  for (const StereoPoint* p : order) {
    if (static_cast<int>(out.size()) >= options.max_points_per_pair) break;
    const Eigen::Vector3d ned = rig_ned + ned_from_camera * p->xyz;
    const double var_down = (ned_from_camera * p->cov * ned_from_camera.transpose())(2, 2);
    if (!ned.allFinite() || !(var_down >= 0) || var_down > options.max_sigma_up_m * options.max_sigma_up_m) continue;
    const double up_m = -(vehicle.depth_m + ned.z());
    if (vehicle.altitude_m > 0 && std::abs(up_m + vehicle.depth_m + vehicle.altitude_m) > options.max_relief_m)
      continue;
    SeabedPoint s;
    s.east_north_up_m = {vehicle.east_m + ned.y(), vehicle.north_m + ned.x(), up_m};
    s.sigma_up_m = std::sqrt(var_down);
    s.views = 2;
    out.push_back(s);
  }
  return out;
}

}  // namespace seamap
