#include "core/nav/nav_series.h"

#include <algorithm>
#include <cmath>

#include "core/nav/nav_values.h"

namespace seamap {
namespace {

double Lerp(double a, double b, double f) {
  return a + (b - a) * f;
}

}  // namespace

NavSeries::NavSeries(const std::vector<NavRecord>& records) {
  for (const NavRecord& record : records)
    if (record.time_s) records_.push_back(record);
  std::stable_sort(records_.begin(), records_.end(),
                   [](const NavRecord& a, const NavRecord& b) { return *a.time_s < *b.time_s; });
}

std::string NavSeries::SpanText() const {
  if (empty()) return "(no timed records)";
  return "[" + FormatNumber(first_time_s()) + ", " + FormatNumber(last_time_s()) + "] s";
}

std::optional<VehiclePose> NavSeries::PoseAt(double t) const {
  if (records_.empty() || !std::isfinite(t)) return std::nullopt;
  if (t < first_time_s() || t > last_time_s()) return std::nullopt;
  // The first record after t: the one before it is the last at or before t,
  // so the two times always differ.
  auto after = std::upper_bound(records_.begin(), records_.end(), t,
                                [](double time, const NavRecord& r) { return time < *r.time_s; });
  if (after == records_.end()) return records_.back().pose;  // t is the last time
  const NavRecord& before = *(after - 1);
  const double f = (t - *before.time_s) / (*after->time_s - *before.time_s);
  const VehiclePose& a = before.pose;
  const VehiclePose& b = after->pose;
  VehiclePose pose;
  pose.east_m = Lerp(a.east_m, b.east_m, f);
  pose.north_m = Lerp(a.north_m, b.north_m, f);
  pose.altitude_m = Lerp(a.altitude_m, b.altitude_m, f);
  pose.depth_m = Lerp(a.depth_m, b.depth_m, f);
  pose.pitch_deg = Lerp(a.pitch_deg, b.pitch_deg, f);
  pose.roll_deg = Lerp(a.roll_deg, b.roll_deg, f);
  const double turn = std::remainder(b.heading_deg - a.heading_deg, 360.0);
  double heading = std::fmod(a.heading_deg + turn * f, 360.0);
  if (heading < 0) heading += 360.0;
  pose.heading_deg = heading >= 360.0 ? 0 : heading;
  return pose;
}

}  // namespace seamap
