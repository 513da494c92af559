#include "core/mosaic/mosaic_plan.h"

#include <algorithm>
#include <cmath>

#include "core/camera/frame_projector.h"
#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

MosaicPlan PlanMosaic(const MapSettings& map, const CameraModel& camera, const LocalFrame& frame,
                      const std::vector<FrameSpec>& frames, int channels) {
  MosaicPlan plan;
  plan.channels = channels;
  std::vector<double> altitudes, easts, norths;
  double max_alt = 0;
  for (const auto& f : frames) {
    altitudes.push_back(f.pose.altitude_m);
    easts.push_back(f.pose.east_m);
    norths.push_back(f.pose.north_m);
    max_alt = std::max(max_alt, f.pose.altitude_m);
  }
  const double median_alt = frames.empty() ? 2.0 : Median(altitudes);
  plan.gsd_m = GroundSampleDistance(camera, median_alt);
  plan.latitude = frame.ToLatLon({Median(easts), Median(norths)}).lat;
  plan.base_zoom =
      map.base_zoom ? *map.base_zoom : ZoomForGroundSampleDistance(plan.gsd_m, plan.latitude, map.tile_size);
  plan.base_zoom = std::clamp(plan.base_zoom, 0, 30);
  if (map.min_zoom) {
    plan.min_zoom = std::min(*map.min_zoom, plan.base_zoom);
    return plan;
  }
  // The zoom at which the whole survey (positions plus the largest footprint
  // radius) spans at most one tile.
  double extent = 0;
  if (!frames.empty()) {
    auto [e0, e1] = std::minmax_element(easts.begin(), easts.end());
    auto [n0, n1] = std::minmax_element(norths.begin(), norths.end());
    const double radius = max_alt * std::hypot(camera.width / camera.fx, camera.height / camera.fy) / 2;
    extent = std::max(*e1 - *e0, *n1 - *n0) + 2 * radius;
  }
  int z = plan.base_zoom;
  while (z > 0 && extent > MetersPerPixel(plan.latitude, z, map.tile_size) * map.tile_size) --z;
  plan.min_zoom = z;
  return plan;
}

}  // namespace seamap
