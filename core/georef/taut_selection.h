#pragma once
// Which keyframes were taken while the tether was taut, and where each of
// those puts the vehicle (its target in the working frame). Before any fit
// the rules are the paper's, made precise: straight, steady towing for t_c
// after a turn, a moving, consistent buoy; the towing direction is the
// buoy's own, from a window of fixes. After a fit the mapped SLAM path and
// the tether model tell where the tether ran and when it was slack.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/georef/buoy_track.h"
#include "core/georef/depth_profile.h"
#include "core/georef/georef_options.h"
#include "core/georef/similarity.h"
#include "core/georef/slam_path.h"

namespace seamap {

// What every round needs, computed once per sub-map.
struct SubmapContext {
  SubmapContext(const SlamPath& path, const BuoyTrack& buoy, const DepthProfile& depth, const GeorefOptions& options);

  const SlamPath& path;
  const BuoyTrack& buoy;
  const GeorefOptions& options;
  std::vector<std::optional<double>> depth_m;  // per keyframe, when known
  std::vector<double> reach_m;                 // per keyframe (0 without depth or too deep)
  std::vector<std::string> static_reason;      // no_depth, too_deep, gps_gap; "" otherwise
  std::vector<double> leg_speed_mps;           // the buoy's median speed per SLAM leg
  std::vector<double> dt_s;                    // the time each keyframe stands for
};

// Per keyframe: why it cannot be used ("" = taut), and its target.
struct TargetSet {
  std::vector<std::string> reason;
  std::vector<Eigen::Vector3d> target_enu_m;  // buoy + reach along the towing direction, up = -depth
  std::vector<Eigen::Vector2d> towing;        // unit towing direction (east, north)
  std::vector<double> sigma_m;                // the target's horizontal sigma per axis, every term
  std::vector<double> gps_sigma_m;            // its GPS part alone
  bool model = false;                         // directions from the tether model
};

TargetSet SelectFromBuoy(const SubmapContext& context);

// heading_sigma_rad: how well the fit knows the heading (the model
// direction's error). Needs a fit with scale > 0.
TargetSet SelectWithModel(const SubmapContext& context, const Similarity& fit, double heading_sigma_rad);

}  // namespace seamap
