#pragma once
// Buoy-GPS georeferencing of one SLAM sub-map: which keyframes were towed on
// a taut tether, where that puts the vehicle, and the similarity (scale,
// rotation, translation) from SLAM coordinates to the working frame (metres
// east, north, up), with the degenerate cases refused and the fit's expected
// error. See docs/GEOREF.md.
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/georef/buoy_track.h"
#include "core/georef/depth_profile.h"
#include "core/georef/fit_quality.h"
#include "core/georef/georef_options.h"
#include "core/georef/similarity.h"
#include "core/georef/slam_path.h"
#include "core/georef/tum_trajectory.h"

namespace seamap {

struct KeyframeGeoref {
  double time_s = 0;
  int line = 0;
  Eigen::Vector3d position_enu_m = Eigen::Vector3d::Zero();    // the keyframe mapped by the fit
  Eigen::Matrix3d enu_from_cam = Eigen::Matrix3d::Identity();  // its orientation mapped
  double heading_deg = 0;                                      // of the body's forward axis
  std::optional<double> depth_m;                               // measured
  bool good = false;                                           // in the final fit
  std::string reason;                                          // why not ("" when good)
  double sigma_m = 0;  // predicted horizontal error (2D RMS); 0 where the method has none
  bool has_target = false;
  Eigen::Vector3d target_enu_m = Eigen::Vector3d::Zero();
};

struct SubmapGeoref {
  std::string source;
  bool fitted = false;  // a transform exists (false only when degenerate from the start)
  Similarity transform;
  bool degenerate = false;
  std::string reason;  // why degenerate
  std::string method;  // "tether", "umeyama" or "triangle"
  std::vector<KeyframeGeoref> keyframes;
  int good = 0;
  std::map<std::string, int> rejected;  // reason -> keyframes
  double rmse_m = 0;                    // horizontal RMS residual of the good keyframes
  double gps_sigma_m = 0;
  std::string gps_sigma_source;
  double fix_rate_hz = 0;
  double good_duration_s = 0;
  double n_eff = 0;               // distinct fixes behind the good keyframes
  double predicted_rmse_m = 0;    // expected error over all keyframes (tether: every term; else the GPS bound)
  double gps_bound_rmse_m = 0;    // the GPS-limited error over all keyframes (the bound)
  double model_bound_rmse_m = 0;  // tether: the same with the current, reach, lag it estimates unknown
  // --method tether: the tether and buoy model fitted with the similarity.
  double reach_factor = 1, reach_factor_sigma = 0;
  bool reach_estimated = false;
  Eigen::Vector2d current_mps = Eigen::Vector2d::Zero();  // east, north, carrying the buoy
  Eigen::Vector2d current_sigma_mps = Eigen::Vector2d::Zero();
  double lag_s = 0, lag_sigma_s = 0;  // a fix stamped t shows the buoy at t - lag
  // The buoy's extra distance behind the vehicle that the free fit's reach
  // and lag together put it at, c_t (k - 1) + |v| lag: for a buoy in the
  // wake the two are one shift, and only this sum is seen.
  double along_track_offset_m = 0, along_track_offset_sigma_m = 0;
  double reach_lag_correlation = 0;    // in the free fit
  bool reach_lag_separable = true;     // |correlation| < 0.9
  double unseen_offset_rmse_m = 0;     // towed_fit.h: what an offset along the track no fix shows may do
  double selection_spread_rmse_m = 0;  // towed_fit.h: reach, lag or both, where they trade
  bool current_estimated = false, wake_estimated = false, lag_estimated = false;
  double wake_share = 0, wake_share_sigma = 0;
  double variance_factor = 1, correlation_factor = 1;
  double taut_model_sigma_m = 0, slack_model_sigma_m = 0;
  int fixes_used = 0, taut_fixes = 0;
  double along_track_bias_m = 0;
  double eigen_ratio = 0;
  double reach_m = 0;      // median over the keyframes
  double taut_time_s = 0;  // t_c at the median buoy speed
  FitUncertainty uncertainty;
  int rounds = 0;
  int outliers = 0;
  std::array<int, 3> triangle{-1, -1, -1};  // keyframe indices (--method triangle)
  double triangle_area_m2 = 0;
  std::string forward_axis;  // "image_up" (camera -y) or "optical_axis" (+z)
  std::vector<SuspectedReset> resets;
  std::vector<std::string> warnings;
};

// Throws InputError(source, ...) when no keyframe falls within the buoy's
// time span (both spans in the message). Degenerate geometry is returned
// (degenerate = true, reason), not thrown.
SubmapGeoref GeoreferenceSubmap(const std::string& source, const std::vector<Keyframe>& keyframes,
                                const BuoyTrack& buoy, const DepthProfile& depth, const GeorefOptions& options);

// The heading (degrees clockwise from north, [0, 360)) of a camera whose
// orientation in east-north-up is `enu_from_cam`: the forward axis is image-up
// (camera -y) when the optical axis is within 45 degrees of vertical, else the
// optical axis.
double CameraHeadingDeg(const Eigen::Matrix3d& enu_from_cam, bool image_up);

}  // namespace seamap
