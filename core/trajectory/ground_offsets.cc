#include "core/trajectory/ground_offsets.h"

#include <cmath>

#include "core/camera/frame_projector.h"

namespace seamap {

double WrapAngle(double rad) {
  return std::atan2(std::sin(rad), std::cos(rad));
}

std::optional<std::vector<cv::Point2d>> GroundOffsets(const CameraModel& camera, const VehiclePose& pose,
                                                      const std::vector<cv::Point2f>& ideal_px) {
  VehiclePose level = pose;
  level.east_m = level.north_m = 0;
  level.heading_deg = 0;
  const auto h = GroundFromImage(camera, level);
  if (!h) return std::nullopt;
  std::vector<cv::Point2d> out(ideal_px.size());
  for (size_t k = 0; k < ideal_px.size(); ++k) {
    const Eigen::Vector3d g = *h * Eigen::Vector3d(ideal_px[k].x, ideal_px[k].y, 1.0);
    out[k] = {g.x() / g.z(), g.y() / g.z()};
  }
  return out;
}

}  // namespace seamap
