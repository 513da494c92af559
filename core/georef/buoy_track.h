#pragma once
// The buoy's GPS fixes in the working frame (metres east, north), their noise
// and local fits: at any time, a quadratic in time fitted to the fixes of a
// window gives the buoy's position and towing velocity with their errors.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace seamap {

struct BuoyFix {
  double time_s = 0;
  Eigen::Vector2d position_en_m = Eigen::Vector2d::Zero();  // east, north in the working frame
  double sigma_m = 0;  // horizontal sigma per axis; 0 = unknown (then hdop or the scatter decide)
  double hdop = 0;     // 0 = unknown
  int line = 0;        // in the buoy file
};

// The buoy's position and velocity at one time from the fixes around it.
struct BuoyLocalFit {
  bool ok = false;  // enough fixes on both sides
  Eigen::Vector2d position_en_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity_en_mps = Eigen::Vector2d::Zero();
  double position_sigma_m = 0;     // per axis, from the fit
  double direction_sigma_rad = 0;  // of the velocity's direction, from the fit
  int fixes = 0;                   // used
  int dropped = 0;                 // beyond 3.5 sigma of the fit
};

class BuoyTrack {
 public:
  // Fixes in any order; sorted by time here. Per-fix sigmas are completed:
  // given ones kept, hdop times a range error (UERE) estimated from the
  // scatter, else the scatter's sigma (see EstimateScatterSigma).
  explicit BuoyTrack(std::vector<BuoyFix> fixes);

  const std::vector<BuoyFix>& fixes() const { return fixes_; }
  double start_s() const { return fixes_.front().time_s; }
  double end_s() const { return fixes_.back().time_s; }
  double fix_rate_hz() const { return fix_rate_hz_; }                // 1 / median interval
  double sigma_m() const { return sigma_m_; }                        // median per-fix sigma, floored at 1 cm
  const std::string& sigma_source() const { return sigma_source_; }  // "sigma_m", "hdop" or "scatter"

  // A fix no more than max_gap_s before and after t.
  bool Bracketed(double time_s, double max_gap_s) const;
  // Sigma of the fix nearest in time.
  double SigmaAt(double time_s) const;
  // Median speed over [from_s, to_s] from 10 s chords of the fixes; 0 without any.
  double MedianSpeed(double from_s, double to_s) const;
  // RMS horizontal distance of the fixes in [from_s, to_s] from their centroid.
  double Spread(double from_s, double to_s) const;

  // A quadratic in time fitted to the fixes within t +- window_s / 2 and
  // inside [from_s, to_s], weighted by 1 / sigma^2; fixes beyond 3.5 sigma
  // (radially) dropped and the fit repeated. Needs 4 fixes, one on each side of t.
  BuoyLocalFit FitAt(double time_s, double window_s, double from_s, double to_s) const;

 private:
  std::vector<BuoyFix> fixes_;
  double fix_rate_hz_ = 1;
  double sigma_m_ = 0.01;
  std::string sigma_source_;
};

// The sigma per axis of the fixes' noise from their scatter: each fix against
// the line through its two neighbours (var = sigma^2 (1 + a^2 + b^2), a, b the
// interpolation weights), median-based so multipath jumps do not count. Smooth
// towing bends a 1 Hz track by millimetres, so this sees the GPS alone. When
// hdop is given the residuals are divided by it first (the result is then a
// range error, to be multiplied by each fix's hdop).
double EstimateScatterSigma(const std::vector<BuoyFix>& fixes, bool per_hdop);

}  // namespace seamap
