#include "core/georef/slam_path.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/util/statistics.h"

namespace seamap {
namespace {

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (a.norm() == 0 || b.norm() == 0) return 0;
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

}  // namespace

SlamPath::SlamPath(const std::vector<Keyframe>& keyframes, const Options& options) {
  for (const Keyframe& k : keyframes) {
    times_.push_back(k.time_s);
    lines_.push_back(k.line);
    positions_.push_back(k.position_slam);
  }
  const size_t n = times_.size();
  turning_.assign(n, false);
  const double half = options.turn_window_s / 2;
  for (size_t i = 0; i < n; ++i) {
    const double t = times_[i];
    const Eigen::Vector3d back = PositionAt(t) - PositionAt(t - half);
    const Eigen::Vector3d ahead = PositionAt(t + half) - PositionAt(t);
    turning_[i] = AngleDeg(back, ahead) > options.turn_angle_deg;
  }
  leg_.assign(n, -1);
  since_turn_.assign(n, 0);
  double last_turn = n ? times_[0] : 0;
  for (size_t i = 0; i < n; ++i) {
    if (turning_[i]) {
      last_turn = times_[i];
      continue;
    }
    since_turn_[i] = times_[i] - last_turn;
    if (i == 0 || turning_[i - 1]) legs_.push_back({times_[i], times_[i]});
    legs_.back().end_s = times_[i];
    leg_[i] = static_cast<int>(legs_.size()) - 1;
  }
  // The scatter of each keyframe about the line through its neighbours.
  std::vector<double> normalised;
  for (size_t i = 1; i + 1 < n; ++i) {
    const double t0 = times_[i - 1], t1 = times_[i], t2 = times_[i + 1];
    if (turning_[i] || !(t2 > t0)) continue;
    const double b = (t1 - t0) / (t2 - t0), a = 1 - b;
    const Eigen::Vector3d r = positions_[i] - (a * positions_[i - 1] + b * positions_[i + 1]);
    for (int axis = 0; axis < 3; ++axis) normalised.push_back(r[axis] * r[axis] / (1 + a * a + b * b));
  }
  noise_sigma_ = normalised.empty() ? 0 : std::sqrt(Median(normalised) / 0.4549);
}

Eigen::Vector3d SlamPath::PositionAt(double t) const {
  if (times_.empty()) return Eigen::Vector3d::Zero();
  if (t <= times_.front()) return positions_.front();
  if (t >= times_.back()) return positions_.back();
  const size_t j = std::upper_bound(times_.begin(), times_.end(), t) - times_.begin();
  const double f = (t - times_[j - 1]) / (times_[j] - times_[j - 1]);
  return (1 - f) * positions_[j - 1] + f * positions_[j];
}

Eigen::Vector3d SlamPath::DirectionAt(double t, double half, double from_s, double to_s) const {
  const double lo = std::max(from_s, t - half), hi = std::min(to_s, t + half);
  if (!(hi > lo)) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d chord = PositionAt(hi) - PositionAt(lo);
  const double norm = chord.norm();
  return norm > 0 ? Eigen::Vector3d(chord / norm) : Eigen::Vector3d::Zero();
}

double SlamPath::SpeedAt(double t, double half, double from_s, double to_s) const {
  const double lo = std::max(from_s, t - half), hi = std::min(to_s, t + half);
  if (!(hi > lo)) return 0;
  return (PositionAt(hi) - PositionAt(lo)).norm() / (hi - lo);
}

double SlamPath::Straightness(double from_s, double to_s) const {
  double arc = 0;
  Eigen::Vector3d previous = PositionAt(from_s);
  for (size_t i = 0; i < times_.size(); ++i) {
    if (times_[i] <= from_s || times_[i] >= to_s) continue;
    arc += (positions_[i] - previous).norm();
    previous = positions_[i];
  }
  arc += (PositionAt(to_s) - previous).norm();
  const double chord = (PositionAt(to_s) - PositionAt(from_s)).norm();
  return arc > 0 ? chord / arc : 0;
}

double SlamPath::SpeedVariation(double from_s, double to_s) const {
  std::vector<double> speeds;
  for (size_t i = 1; i < times_.size(); ++i) {
    if (times_[i - 1] < from_s || times_[i] > to_s) continue;
    speeds.push_back((positions_[i] - positions_[i - 1]).norm() / (times_[i] - times_[i - 1]));
  }
  if (speeds.size() < 2) return 0;
  double mean = 0, sq = 0;
  for (double s : speeds) mean += s;
  mean /= speeds.size();
  for (double s : speeds) sq += (s - mean) * (s - mean);
  return mean > 0 ? std::sqrt(sq / (speeds.size() - 1)) / mean : 0;
}

std::vector<SuspectedReset> SlamPath::SuspectedResets() const {
  std::vector<double> steps;
  for (size_t i = 1; i < times_.size(); ++i) steps.push_back((positions_[i] - positions_[i - 1]).norm());
  const double median = Median(steps);
  std::vector<SuspectedReset> resets;
  for (size_t i = 1; i < times_.size(); ++i) {
    std::ostringstream why;
    why.precision(3);
    const double gap = times_[i] - times_[i - 1];
    if (gap > 30) {
      why << "a " << gap << " s gap after the previous keyframe";
    } else if (median > 0 && steps[i - 1] > 20 * median) {
      why << "a jump of " << steps[i - 1] / median << " times the median step";
    } else {
      continue;
    }
    resets.push_back({lines_[i], why.str() + ": a SLAM reset? give each part as its own --keyframes file"});
  }
  return resets;
}

}  // namespace seamap
