#pragma once
// The towed-buoy fit's problem (towed_fit.h): its parameters, the model buoy
// towed behind the mapped path, and every fix's residual against it with
// their Jacobian. Internal to FitTowedBuoy (towed_fit.cc).
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/georef/buoy_track.h"
#include "core/georef/similarity.h"
#include "core/georef/slam_path.h"
#include "core/georef/towed_fit.h"

namespace seamap::towed_fit {

// rotation (3), log scale, translation (3), log reach factor, wake share, current (2), the fixes' lag
constexpr int kParams = 12;
using Params = Eigen::Matrix<double, kParams, 1>;
using ParamMatrix = Eigen::Matrix<double, kParams, kParams>;

// Per keyframe value interpolated in time (values <= 0 skipped by the caller's choice of fill).
class TimeSeries {
 public:
  TimeSeries(const SlamPath& path, std::vector<double> values) : path_(path), values_(std::move(values)) {}
  double At(double t) const;

 private:
  const SlamPath& path_;
  std::vector<double> values_;
};

// Fills gaps (values <= 0 or NaN) from the nearest known neighbour.
std::vector<double> Filled(const std::vector<double>& values, double fallback);

struct Model {
  Similarity fit;
  double reach_factor = 1;
  double wake_share = 0;
  Eigen::Vector2d current_mps = Eigen::Vector2d::Zero();
  double lag_s = 0;  // a fix stamped t shows the buoy at t - lag
};

struct Fix {
  double time_s;
  Eigen::Vector2d position;
  double sigma;
};

// The model buoy at each fix, and what the tether did there.
struct Simulation {
  std::vector<Eigen::Vector2d> buoy;    // per fix
  std::vector<Eigen::Vector2d> towing;  // unit, buoy to vehicle, per fix
  std::vector<bool> taut, settled;      // per fix
  std::vector<double> start_sigma_m;    // per fix, what the buoy's unknown start may still leave (0 once settled)
  std::vector<bool> keyframe_taut;      // per keyframe (settled too)
};

class Problem {
 public:
  Problem(const SlamPath& path, const std::vector<double>& reach_m, const std::vector<double>& depth_m,
          const BuoyTrack& buoy, const Similarity& start, double slam_sigma, const TowedFitOptions& options);

  size_t fixes() const { return fixes_.size(); }
  const std::vector<Fix>& fix_list() const { return fixes_; }
  const Eigen::Vector3d& centroid() const { return centroid_; }

  // The start: the rough similarity, a buoy half tractrix, half wake follower.
  Params Initial() const;
  Model ModelAt(const Params& theta) const;
  // The model buoy every options.step_s along the mapped path, sampled at the fixes.
  Simulation Simulate(const Model& m) const;
  // Horizontal residuals of the fixes (2 per fix), then the keyframes' heights.
  Eigen::VectorXd Residuals(const Params& theta, Simulation* sim = nullptr) const;
  size_t depth_count() const;
  // Numeric, central differences.
  Eigen::MatrixXd Jacobian(const Params& theta) const;
  double DepthSigma(const Model& m) const { return std::hypot(options_.depth_sigma_m, m.fit.scale * slam_sigma_); }
  // d(mapped keyframe, east and north) / d(theta).
  Eigen::Matrix<double, 2, kParams> KeyframeJacobian(const Model& m, const Eigen::Vector3d& slam) const;

 private:
  const SlamPath& path_;
  TimeSeries reach_;
  std::vector<double> depth_;
  const TowedFitOptions& options_;
  Similarity start_;
  double slam_sigma_;
  double t0_ = 0, t1_ = 0;
  std::vector<Fix> fixes_;
  Eigen::Vector3d centroid_;
};

// The priors: log k about 0, the wake share about 0.5 (information, and theta's offset from their means).
ParamMatrix PriorInformation(const TowedFitOptions& o);
Params PriorOffset(const Params& theta, const TowedFitOptions& o);

}  // namespace seamap::towed_fit
