#include "core/georef/depth_profile.h"

#include <algorithm>
#include <cmath>

namespace seamap {

DepthProfile DepthProfile::Constant(double depth_m) {
  DepthProfile p;
  p.constant_ = depth_m;
  return p;
}

DepthProfile DepthProfile::Samples(std::vector<std::pair<double, double>> samples, double max_gap_s) {
  DepthProfile p;
  std::stable_sort(samples.begin(), samples.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  p.samples_ = std::move(samples);
  p.max_gap_s_ = max_gap_s;
  std::vector<double> sq;  // each sample against the line through its neighbours
  for (size_t j = 1; j + 1 < p.samples_.size(); ++j) {
    const double t0 = p.samples_[j - 1].first, t1 = p.samples_[j].first, t2 = p.samples_[j + 1].first;
    if (!(t2 > t0)) continue;
    const double b = (t1 - t0) / (t2 - t0), a = 1 - b;
    const double r = p.samples_[j].second - (a * p.samples_[j - 1].second + b * p.samples_[j + 1].second);
    sq.push_back(r * r / (1 + a * a + b * b));
  }
  if (!sq.empty()) {
    std::nth_element(sq.begin(), sq.begin() + sq.size() / 2, sq.end());
    p.noise_sigma_ = std::sqrt(sq[sq.size() / 2] / 0.4549);
  }
  return p;
}

std::optional<double> DepthProfile::At(double t) const {
  if (constant_) return constant_;
  if (samples_.empty() || t < samples_.front().first || t > samples_.back().first) return std::nullopt;
  auto after =
      std::lower_bound(samples_.begin(), samples_.end(), t, [](const auto& s, double time) { return s.first < time; });
  if (after->first == t) return after->second;
  const auto& before = *std::prev(after);
  if (after->first - before.first > max_gap_s_) return std::nullopt;
  const double f = (t - before.first) / (after->first - before.first);
  return (1 - f) * before.second + f * after->second;
}

double DepthProfile::Max() const {
  if (constant_) return *constant_;
  double m = 0;
  for (const auto& s : samples_) m = std::max(m, s.second);
  return m;
}

}  // namespace seamap
