#include "core/georef/buoy_track.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/util/statistics.h"

namespace seamap {
namespace {

constexpr double kSigmaFloorM = 0.01;

}  // namespace

double EstimateScatterSigma(const std::vector<BuoyFix>& fixes, bool per_hdop) {
  std::vector<double> normalised;  // squared residual over its expected factor, per axis
  for (size_t j = 1; j + 1 < fixes.size(); ++j) {
    const double t0 = fixes[j - 1].time_s, t1 = fixes[j].time_s, t2 = fixes[j + 1].time_s;
    if (!(t2 > t0) || t2 - t0 > 10) continue;  // across a gap the track may bend
    const double b = (t1 - t0) / (t2 - t0), a = 1 - b;
    const Eigen::Vector2d r =
        fixes[j].position_en_m - (a * fixes[j - 1].position_en_m + b * fixes[j + 1].position_en_m);
    const double scale = per_hdop ? std::max(fixes[j].hdop, 0.1) : 1.0;
    for (int axis = 0; axis < 2; ++axis)
      normalised.push_back(r[axis] * r[axis] / ((1 + a * a + b * b) * scale * scale));
  }
  // The median of a chi-square with one degree of freedom is 0.4549.
  return normalised.empty() ? 0 : std::sqrt(Median(normalised) / 0.4549);
}

BuoyTrack::BuoyTrack(std::vector<BuoyFix> fixes) : fixes_(std::move(fixes)) {
  std::stable_sort(fixes_.begin(), fixes_.end(),
                   [](const BuoyFix& a, const BuoyFix& b) { return a.time_s < b.time_s; });
  std::vector<double> gaps;
  for (size_t j = 1; j < fixes_.size(); ++j)
    if (fixes_[j].time_s > fixes_[j - 1].time_s) gaps.push_back(fixes_[j].time_s - fixes_[j - 1].time_s);
  const double gap = Median(gaps);
  fix_rate_hz_ = gap > 0 ? 1.0 / gap : 1.0;

  const bool all_sigma = std::all_of(fixes_.begin(), fixes_.end(), [](const BuoyFix& f) { return f.sigma_m > 0; });
  const bool all_hdop = std::all_of(fixes_.begin(), fixes_.end(), [](const BuoyFix& f) { return f.hdop > 0; });
  if (all_sigma) {
    sigma_source_ = "sigma_m";
  } else if (all_hdop) {
    sigma_source_ = "hdop";
    const double uere = EstimateScatterSigma(fixes_, true);
    for (BuoyFix& f : fixes_)
      if (!(f.sigma_m > 0)) f.sigma_m = uere * f.hdop;
  } else {
    sigma_source_ = "scatter";
    const double sigma = EstimateScatterSigma(fixes_, false);
    for (BuoyFix& f : fixes_)
      if (!(f.sigma_m > 0)) f.sigma_m = sigma;
  }
  std::vector<double> sigmas;
  for (BuoyFix& f : fixes_) {
    f.sigma_m = std::max(f.sigma_m, kSigmaFloorM);  // or a noise-free track would weigh infinitely
    sigmas.push_back(f.sigma_m);
  }
  sigma_m_ = std::max(Median(sigmas), kSigmaFloorM);
}

bool BuoyTrack::Bracketed(double t, double max_gap_s) const {
  auto after =
      std::lower_bound(fixes_.begin(), fixes_.end(), t, [](const BuoyFix& f, double time) { return f.time_s < time; });
  if (after == fixes_.end()) return false;
  if (after->time_s == t) return true;
  if (after == fixes_.begin()) return false;
  return after->time_s - t <= max_gap_s && t - std::prev(after)->time_s <= max_gap_s;
}

double BuoyTrack::SigmaAt(double t) const {
  auto after =
      std::lower_bound(fixes_.begin(), fixes_.end(), t, [](const BuoyFix& f, double time) { return f.time_s < time; });
  if (after == fixes_.end()) return fixes_.back().sigma_m;
  if (after == fixes_.begin()) return after->sigma_m;
  return (after->time_s - t < t - std::prev(after)->time_s) ? after->sigma_m : std::prev(after)->sigma_m;
}

double BuoyTrack::MedianSpeed(double from_s, double to_s) const {
  std::vector<double> speeds;
  size_t k = 0;
  for (size_t j = 0; j < fixes_.size(); ++j) {
    if (fixes_[j].time_s < from_s || fixes_[j].time_s > to_s) continue;
    k = std::max(k, j);
    while (k < fixes_.size() && fixes_[k].time_s < fixes_[j].time_s + 10) ++k;
    if (k >= fixes_.size() || fixes_[k].time_s > to_s || fixes_[k].time_s - fixes_[j].time_s > 15) continue;
    speeds.push_back((fixes_[k].position_en_m - fixes_[j].position_en_m).norm() /
                     (fixes_[k].time_s - fixes_[j].time_s));
  }
  return Median(speeds);
}

double BuoyTrack::Spread(double from_s, double to_s) const {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int n = 0;
  for (const BuoyFix& f : fixes_)
    if (f.time_s >= from_s && f.time_s <= to_s) sum += f.position_en_m, ++n;
  if (n == 0) return 0;
  const Eigen::Vector2d centroid = sum / n;
  double sq = 0;
  for (const BuoyFix& f : fixes_)
    if (f.time_s >= from_s && f.time_s <= to_s) sq += (f.position_en_m - centroid).squaredNorm();
  return std::sqrt(sq / n);
}

BuoyLocalFit BuoyTrack::FitAt(double t, double window_s, double from_s, double to_s) const {
  const double lo = std::max(from_s, t - window_s / 2), hi = std::min(to_s, t + window_s / 2);
  auto first =
      std::lower_bound(fixes_.begin(), fixes_.end(), lo, [](const BuoyFix& f, double time) { return f.time_s < time; });
  std::vector<const BuoyFix*> window;
  for (auto it = first; it != fixes_.end() && it->time_s <= hi; ++it) window.push_back(&*it);
  std::vector<bool> used(window.size(), true);
  BuoyLocalFit fit;
  // One fix at a time, the worst beyond 3.5 sigma: a 20 m multipath jump
  // bends the first fit so far that a cut of everything beyond the bound
  // would drop clean fixes with it. Dropped fixes back within it return.
  for (int round = 0; round < 12; ++round) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Matrix<double, 3, 2> rhs = Eigen::Matrix<double, 3, 2>::Zero();
    int n = 0, before = 0, after = 0;
    for (size_t j = 0; j < window.size(); ++j) {
      if (!used[j]) continue;
      const double dt = window[j]->time_s - t;
      const Eigen::Vector3d a(1, dt, dt * dt);
      const double w = 1.0 / (window[j]->sigma_m * window[j]->sigma_m);
      normal += w * a * a.transpose();
      rhs += w * a * window[j]->position_en_m.transpose();
      ++n;
      before += dt < 0;
      after += dt > 0;
    }
    if (n < 4 || before == 0 || after == 0) return BuoyLocalFit{};
    const Eigen::Matrix3d cov = normal.inverse();  // the coefficients' covariance (weights are 1 / sigma^2)
    const Eigen::Matrix<double, 3, 2> coef = cov * rhs;
    fit.ok = true;
    fit.position_en_m = coef.row(0).transpose();
    fit.velocity_en_mps = coef.row(1).transpose();
    fit.position_sigma_m = std::sqrt(std::max(cov(0, 0), 0.0));
    fit.direction_sigma_rad = std::sqrt(std::max(cov(1, 1), 0.0)) / std::max(fit.velocity_en_mps.norm(), 1e-6);
    fit.fixes = n;
    fit.dropped = static_cast<int>(window.size()) - n;
    int worst = -1;
    double worst_ratio = 3.5;
    bool readmitted = false;
    for (size_t j = 0; j < window.size(); ++j) {
      const double dt = window[j]->time_s - t;
      const Eigen::Vector2d model =
          coef.row(0).transpose() + dt * coef.row(1).transpose() + dt * dt * coef.row(2).transpose();
      const double ratio = (window[j]->position_en_m - model).norm() / window[j]->sigma_m;
      if (used[j] && ratio > worst_ratio) worst_ratio = ratio, worst = static_cast<int>(j);
      if (!used[j] && ratio <= 3.5) used[j] = true, readmitted = true;
    }
    if (worst >= 0) used[worst] = false;
    if (worst < 0 && !readmitted) break;
  }
  return fit;
}

}  // namespace seamap
