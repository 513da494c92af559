#include "core/controllers/trajectory_georef.h"

#include <cmath>
#include <map>
#include <utility>

#include "core/controllers/mission_trajectory_io.h"
#include "core/nav/csv_table.h"
#include "core/util/error.h"

namespace seamap {

TrajectoryGeoref GeoreferenceTrajectory(const std::vector<TrajectoryRow>& rows, const LocalFrame& frame,
                                        BuoyGeorefOptions options) {
  // One keyframe per time (the last row at a time wins, as NavSeries has it), about the survey's origin.
  std::map<double, size_t> by_time;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].time_s)
      throw InputError(options.keyframes_source, 0, "time_s",
                       "frame '" + Shorten(rows[i].image, 100) + "' has no time to match against the buoy's fixes");
    by_time[*rows[i].time_s] = i;
  }
  options.keyframes.clear();
  for (const auto& [time_s, i] : by_time) options.keyframes.push_back(PoseKeyframe(time_s, rows[i].pose, 0));
  if (options.keyframes.size() < 2)
    throw InputError(options.keyframes_source, 0, "time_s", "fewer than two timed frames to georeference");
  options.origin = frame.origin();  // the working frame is the survey's: positions come back in it
  options.out.clear();
  const std::string source = options.keyframes_source;
  const BuoyGeorefResult done = BuoyGeoref(std::move(options)).Run();
  const SubmapGeoref& fit = done.fits.front();

  std::map<double, const KeyframeGeoref*> placed;
  for (const KeyframeGeoref& k : fit.keyframes) placed[k.time_s] = &k;
  // The fit's turn about the vertical: where it sends north.
  const Eigen::Vector3d north = fit.transform.rotation * Eigen::Vector3d::UnitY();
  const double turn_deg = std::atan2(north.x(), north.y()) * 180 / M_PI;

  TrajectoryGeoref out;
  out.scale = fit.transform.scale;
  out.rotation_deg = turn_deg;
  out.predicted_rmse_m = fit.predicted_rmse_m;
  out.residual_rmse_m = fit.rmse_m;
  out.keyframes = done.keyframes, out.good = done.good;
  for (const TrajectoryRow& row : rows) {
    TrajectoryRow moved = row;
    const auto k = placed.find(*row.time_s);
    if (k == placed.end()) throw InputError(source, 0, "time_s", "a frame's keyframe was not mapped");
    moved.pose.east_m = k->second->position_enu_m.x();
    moved.pose.north_m = k->second->position_enu_m.y();
    moved.pose.heading_deg = std::fmod(row.pose.heading_deg + turn_deg + 720, 360.0);
    if (!k->second->good) moved.flags += std::string(moved.flags.empty() ? "" : ";") + "buoy_unused";
    out.rows.push_back(std::move(moved));
  }
  if (!rows.empty())
    out.shift_m = std::hypot(out.rows.front().pose.east_m - rows.front().pose.east_m,
                             out.rows.front().pose.north_m - rows.front().pose.north_m);
  return out;
}

}  // namespace seamap
