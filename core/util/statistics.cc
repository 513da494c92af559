#include "core/util/statistics.h"

#include <algorithm>
#include <cmath>

namespace seamap {

double Median(std::vector<double> values) {
  if (values.empty()) return 0;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  return values[mid];
}

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double rank = std::clamp(p, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(rank));
  const size_t above = std::min(below + 1, values.size() - 1);
  const double w = rank - static_cast<double>(below);
  if (w == 0) return values[below];
  // (1 - w) a + w b, not a + w (b - a): at w = 0.5 this is exactly (a + b) / 2.
  return (1 - w) * values[below] + w * values[above];
}

}  // namespace seamap
