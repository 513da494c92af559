#include "core/mosaic/mosaic_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/camera/frame_projector.h"
#include "core/geo/web_mercator.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

std::string Megabytes(double bytes) {
  char text[64];
  std::snprintf(text, sizeof text, "%.0f MB", bytes / (1 << 20));
  return text;
}

// A frame at the median altitude at `zoom`, in global pixels: its nadir box
// (width x height), or turned 45 degrees (the diagonal both ways).
struct TypicalBox {
  double width_px, height_px, diagonal_px;
};
TypicalBox TypicalFrame(const MosaicPlan& plan, const CameraModel& camera, int zoom, int tile_size) {
  const double m_per_px = MetersPerPixel(plan.latitude, zoom, tile_size);
  const double w = plan.gsd_m * camera.width / m_per_px + 1, h = plan.gsd_m * camera.height / m_per_px + 1;
  return {w, h, std::hypot(w, h)};
}

}  // namespace

double FramePaintBytes(double width_px, double height_px, int tile_size, int channels) {
  const double tiles = (std::floor(width_px / tile_size) + 2) * (std::floor(height_px / tile_size) + 2);
  const double tile_bytes = double{4} * (channels + 1) * tile_size * tile_size;  // sums and weights, float
  return width_px * height_px * (channels + 1) + tiles * tile_bytes;
}

void CheckPlanFitsMemory(const MosaicPlan& plan, const CameraModel& camera, int tile_size, int memory_cap_mb,
                         const std::string& source) {
  const double cap = static_cast<double>(memory_cap_mb) * (1 << 20);
  auto needs = [&](int zoom) {
    const TypicalBox box = TypicalFrame(plan, camera, zoom, tile_size);
    return FramePaintBytes(box.width_px, box.height_px, tile_size, plan.channels);
  };
  const double need = needs(plan.base_zoom);
  if (need <= cap) return;
  int fits = plan.base_zoom;
  while (fits > 0 && needs(fits) > cap) --fits;
  char gsd[32];
  std::snprintf(gsd, sizeof gsd, "%.1f mm", plan.gsd_m * 1000);
  throw InputError(source, 0, "base_zoom",
                   "base zoom " + std::to_string(plan.base_zoom) + " cannot be built within memory_cap_mb " +
                       std::to_string(memory_cap_mb) + ": one frame (ground sample distance " + gsd + ") would need " +
                       Megabytes(need) + " of tiles; use --base-zoom " + std::to_string(fits) +
                       " or lower, or raise memory_cap_mb");
}

double FramePaintLimitBytes(const MosaicPlan& plan, const CameraModel& camera, int tile_size, int memory_cap_mb) {
  const TypicalBox box = TypicalFrame(plan, camera, plan.base_zoom, tile_size);
  return std::max(static_cast<double>(memory_cap_mb) * (1 << 20),
                  8 * FramePaintBytes(box.diagonal_px, box.diagonal_px, tile_size, plan.channels));
}

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
