#include "core/trajectory/trajectory_eval.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/camera/frame_projector.h"
#include "core/trajectory/track_pairing.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

AxisStats Stats(const std::vector<double>& errors) {
  if (errors.empty()) return {kNaN, kNaN, kNaN};
  double sum = 0, sum_sq = 0;
  for (double e : errors) sum += e, sum_sq += e * e;
  const double n = static_cast<double>(errors.size());
  AxisStats s;
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  s.std = std::sqrt(std::max(0.0, sum_sq / n - s.mean * s.mean));
  return s;
}

struct Ned {
  double n = 0, e = 0, d = 0;
};

// A NED vector in the body frame (x bow, y starboard, z down) of a vehicle
// with the given attitude: NedFromBody^T v.
std::array<double, 3> ToBody(const Ned& v, const VehiclePose& attitude) {
  const Eigen::Vector3d body = NedFromBody(attitude).transpose() * Eigen::Vector3d(v.n, v.e, v.d);
  return {body.x(), body.y(), body.z()};
}

Ned Position(const VehiclePose& p) {
  return {p.north_m, p.east_m, p.depth_m};
}

void VelocityErrors(const std::vector<const NavRecord*>& est, const std::vector<const NavRecord*>& truth,
                    TrajectoryErrors* out) {
  std::array<std::vector<double>, 3> errors;
  for (size_t k = 1; k + 1 < truth.size(); ++k) {
    const auto &t0 = truth[k - 1]->time_s, &t1 = truth[k + 1]->time_s;
    if (!t0 || !t1 || !(*t1 > *t0)) continue;
    const double dt = *t1 - *t0;
    auto velocity = [&](const NavRecord* a, const NavRecord* b) {
      const Ned pa = Position(a->pose), pb = Position(b->pose);
      return ToBody({(pb.n - pa.n) / dt, (pb.e - pa.e) / dt, (pb.d - pa.d) / dt}, truth[k]->pose);
    };
    const auto v_est = velocity(est[k - 1], est[k + 1]), v_true = velocity(truth[k - 1], truth[k + 1]);
    for (int axis = 0; axis < 3; ++axis) errors[axis].push_back(v_est[axis] - v_true[axis]);
  }
  out->velocity_frames = static_cast<int>(errors[0].size());
  for (int axis = 0; axis < 3; ++axis) out->velocity[axis] = Stats(errors[axis]);
}

// Pairs of frames on different lines whose true centres are closer than
// max_distance_m: the error of their relative position, in mm, sorted.
std::vector<double> CrossPassErrorsMm(const std::vector<LocalXY>& est, const std::vector<LocalXY>& truth,
                                      const std::vector<int>& line, double max_distance_m) {
  // Sweep in east order: only frames within max_distance_m in east can pair.
  std::vector<int> order(truth.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return truth[a].east < truth[b].east; });
  std::vector<double> errors_mm;
  for (size_t a = 0; a < order.size(); ++a) {
    const int i = order[a];
    if (line[i] == kNoLine) continue;
    for (size_t b = a + 1; b < order.size() && truth[order[b]].east - truth[i].east < max_distance_m; ++b) {
      const int j = order[b];
      if (line[j] == kNoLine || line[j] == line[i]) continue;
      const double true_de = truth[i].east - truth[j].east, true_dn = truth[i].north - truth[j].north;
      if (std::hypot(true_de, true_dn) >= max_distance_m) continue;
      const double de = (est[i].east - est[j].east) - true_de, dn = (est[i].north - est[j].north) - true_dn;
      errors_mm.push_back(1000 * std::hypot(de, dn));
    }
  }
  std::sort(errors_mm.begin(), errors_mm.end());
  return errors_mm;
}

}  // namespace

TrajectoryErrors EvaluateTrajectory(const NavTable& estimate, const NavTable& truth, const EvalOptions& options) {
  const TrackPairing pairing = PairFrames(estimate, truth);
  const size_t n = pairing.pairs.size();
  std::vector<const NavRecord*> est_records, true_records;
  std::vector<LocalXY> est_xy, true_xy;
  std::vector<double> true_heading;
  for (const FramePair& p : pairing.pairs) {
    est_records.push_back(&estimate.records[p.estimate]);
    true_records.push_back(&truth.records[p.truth]);
    est_xy.push_back({est_records.back()->pose.east_m, est_records.back()->pose.north_m});
    true_xy.push_back({true_records.back()->pose.east_m, true_records.back()->pose.north_m});
    true_heading.push_back(true_records.back()->pose.heading_deg);
  }

  TrajectoryErrors out;
  out.frames = static_cast<int>(n);
  out.paired_by = pairing.by;
  double sum_sq = 0, sum_sq_north = 0, sum_sq_east = 0;
  for (size_t k = 0; k < n; ++k) {
    const double de = est_xy[k].east - true_xy[k].east, dn = est_xy[k].north - true_xy[k].north;
    const double distance = std::hypot(de, dn);
    sum_sq += distance * distance;
    sum_sq_north += dn * dn;
    sum_sq_east += de * de;
    out.max_error_m = std::max(out.max_error_m, distance);
    out.max_north_m = std::max(out.max_north_m, std::fabs(dn));
    out.max_east_m = std::max(out.max_east_m, std::fabs(de));
    if (k > 0)
      out.path_length_m += std::hypot(true_xy[k].east - true_xy[k - 1].east, true_xy[k].north - true_xy[k - 1].north);
    if (k + 1 == n) out.end_error_m = distance;
  }
  out.ate_m = std::sqrt(sum_sq / n);
  out.rmse_north_m = std::sqrt(sum_sq_north / n);
  out.rmse_east_m = std::sqrt(sum_sq_east / n);
  out.drift_percent = out.path_length_m > 0 ? 100 * out.max_error_m / out.path_length_m : kNaN;

  const std::vector<int> line = SegmentLines(true_heading, true_xy, options.lines);
  out.lines = line.empty() ? 0 : *std::max_element(line.begin(), line.end()) + 1;
  const std::vector<double> cross = CrossPassErrorsMm(est_xy, true_xy, line, options.max_pair_distance_m);
  out.cross_pairs = static_cast<int>(cross.size());
  out.cross_median_mm = cross.empty() ? kNaN : Percentile(cross, 0.5);
  out.cross_p90_mm = cross.empty() ? kNaN : Percentile(cross, 0.9);
  out.cross_max_mm = cross.empty() ? kNaN : cross.back();

  VelocityErrors(est_records, true_records, &out);
  return out;
}

}  // namespace seamap
