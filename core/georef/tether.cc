#include "core/georef/tether.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace seamap {

double TetherReach(double c, double d) {
  if (!(c > 0)) throw std::invalid_argument("tether length must be positive");
  if (!(d >= 0) || d > c) throw std::invalid_argument("depth must be within [0, tether length]");
  return std::sqrt(c * c - d * d);
}

Eigen::Vector2d VehicleFromBuoy(const Eigen::Vector2d& buoy, const Eigen::Vector2d& direction, double reach_m) {
  const double norm = direction.norm();
  if (!(norm > 0)) return buoy;
  return buoy + reach_m * direction / norm;
}

double TautTime(double reach_m, double speed_mps) {
  return 2.0 * reach_m / std::max(speed_mps, 1e-6);
}

double WindowDirectionSigma(double sigma, double speed, double rate, double window_s) {
  return sigma * std::sqrt(12.0) / (std::max(speed, 1e-6) * std::sqrt(rate) * std::pow(window_s, 1.5));
}

double DirectionWindow(double sigma, double speed, double rate, double reach_m) {
  const double allowed_m = std::max(0.5 * sigma, 0.01);
  // c_t sigma sqrt(12) / (|v| sqrt(f) T^1.5) = allowed  =>  T = (...)^(2/3)
  const double t15 = reach_m * sigma * std::sqrt(12.0) / (std::max(speed, 1e-6) * std::sqrt(rate) * allowed_m);
  return std::pow(t15, 2.0 / 3.0);
}

}  // namespace seamap
