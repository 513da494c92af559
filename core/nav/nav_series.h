#pragma once
// The navigation as one time series: the records that have a time, sorted,
// and the pose at any time inside their span. Every caller that places
// something at a time (build's frame matching, stereo-locate --time) uses it,
// so unsorted navigation is interpolated the same way everywhere.
#include <optional>
#include <string>
#include <vector>

#include "core/camera/vehicle_pose.h"
#include "core/nav/nav_table.h"

namespace seamap {

class NavSeries {
 public:
  // The records with a time, stably sorted by it: records that share a time
  // keep their file order, and the last of them is the pose at that time.
  // Records without a time are left out.
  explicit NavSeries(const std::vector<NavRecord>& records);

  bool empty() const { return records_.empty(); }
  const std::vector<NavRecord>& records() const { return records_; }
  // The span (not empty()): the first and last times.
  double first_time_s() const { return *records_.front().time_s; }
  double last_time_s() const { return *records_.back().time_s; }
  // "[first, last] s", or "(no timed records)" when empty.
  std::string SpanText() const;

  // The pose at `time_s`: linear between the records around it in position,
  // altitude, depth, pitch and roll, and along the shorter arc for heading
  // (350 -> 10 passes through 0), in [0, 360). Empty outside the span or for
  // a time that is not finite.
  std::optional<VehiclePose> PoseAt(double time_s) const;

 private:
  std::vector<NavRecord> records_;
};

}  // namespace seamap
