#pragma once
// The vehicle's depth over time: a constant, or samples (a pressure sensor's
// log) interpolated linearly, never across a gap of more than `max_gap_s`.
#include <optional>
#include <utility>
#include <vector>

namespace seamap {

class DepthProfile {
 public:
  static DepthProfile Constant(double depth_m);
  // (time_s, depth_m) pairs, any order.
  static DepthProfile Samples(std::vector<std::pair<double, double>> samples, double max_gap_s = 10);

  // nullopt outside the samples' span or inside a gap.
  std::optional<double> At(double time_s) const;
  bool constant() const { return constant_.has_value(); }
  // The depth's noise (sigma, metres) from the samples' scatter; 0 for a constant.
  double NoiseSigma() const { return noise_sigma_; }
  double Max() const;

 private:
  std::optional<double> constant_;
  std::vector<std::pair<double, double>> samples_;
  double max_gap_s_ = 10;
  double noise_sigma_ = 0;
};

}  // namespace seamap
