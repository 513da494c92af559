#include "core/georef/held_offset.h"

#include <algorithm>
#include <cmath>

namespace seamap {

double HeldOffsetMeanSquare(double offset_m, double sigma_m, const HeldOffsetPrior& prior) {
  const double tau2 = prior.sigma_m * prior.sigma_m;
  if (!(tau2 > 0)) return 0;
  const double s2 = std::max(sigma_m * sigma_m, 1e-12);
  const double exact = std::clamp(prior.exact_share, 0.0, 1.0);
  // The slab's posterior: a Gaussian prior times a Gaussian likelihood.
  const double mean = offset_m * tau2 / (tau2 + s2);
  const double var = tau2 * s2 / (tau2 + s2);
  // The slab's posterior probability, from the estimate's density under
  // each (log densities: a well-seen offset far out underflows both).
  auto log_density = [&](double v) { return -offset_m * offset_m / (2 * v) - 0.5 * std::log(v); };
  const double log_spike = exact > 0 ? std::log(exact) + log_density(s2) : -INFINITY;
  const double log_slab = exact < 1 ? std::log(1 - exact) + log_density(tau2 + s2) : -INFINITY;
  if (log_slab == -INFINITY) return 0;
  const double slab = 1 / (1 + std::exp(log_spike - log_slab));
  return slab * (mean * mean + var);
}

}  // namespace seamap
