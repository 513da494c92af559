#include "core/georef/towed_fit_comparison.h"

#include <algorithm>
#include <cmath>

namespace seamap {

bool MovedBeyondChance(const SlamPath& path, const TowedFitResult& freed, int freed_parameters,
                       const TowedFitResult& held) {
  // chi-square's 3-sigma level (99.73 %) at 1 or 2 degrees of freedom, over them (the header says why)
  const double factor = freed_parameters == 1 ? 9.0 : 11.83 / 2;
  const size_t n = path.size();
  if (held.keyframe_sigma_m.size() != n || freed.keyframe_sigma_m.size() != n) return false;
  double shift_sq = 0, chance_sq = 0;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d x = path.position(i);
    shift_sq += (freed.fit.Apply(x) - held.fit.Apply(x)).head<2>().squaredNorm();
    chance_sq += std::max(std::pow(freed.keyframe_sigma_m[i], 2) - std::pow(held.keyframe_sigma_m[i], 2), 0.0);
  }
  shift_sq /= n;
  chance_sq /= n;
  return shift_sq > factor * chance_sq;
}

void AddSelectionSpread(const SlamPath& path, const std::vector<WeighedFit>& candidates, TowedFitResult* best) {
  const size_t n = path.size();
  if (best->keyframe_sigma_m.size() != n) return;
  double bic_min = candidates.front().bic;
  for (const WeighedFit& c : candidates) bic_min = std::min(bic_min, c.bic);
  std::vector<double> weight;
  double total = 0;
  for (const WeighedFit& c : candidates) total += weight.emplace_back(std::exp(-(c.bic - bic_min) / 2));
  std::vector<double> spread_sq(n, 0.0);  // per keyframe, m^2
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d x = path.position(i);
    const Eigen::Vector2d kept = best->fit.Apply(x).head<2>();
    for (size_t m = 0; m < candidates.size(); ++m)
      spread_sq[i] += weight[m] * (candidates[m].fit->fit.Apply(x).head<2>() - kept).squaredNorm();
    spread_sq[i] /= total;
  }
  best->selection_spread_rmse_m = AddKeyframeVariance(spread_sq, best);
}

}  // namespace seamap
