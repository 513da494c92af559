#pragma once
// The similarity fitted to the buoy's fixes through the tether, jointly: the
// vehicle's target b + c_t u moves with the fit's own rotation (u is the
// mapped towing direction), so fixed targets would weigh heading with the
// vehicle's lever arms where the data sees the buoy's (c_t behind, on
// alternate sides leg by leg). Minimises
//   sum w_i |R (s x_i - o_i) + t - q_i|^2,
// o_i the tether offset c_t,i u_i taken back into SLAM axes by the previous
// rotation, q_i = (buoy east, north, -depth), by alternating a Kabsch step
// (s fixed) and a linear step for s and t (R fixed). docs/GEOREF.md.
#include <vector>

#include <Eigen/Core>

#include "core/georef/similarity.h"

namespace seamap {

// start: the fit with fixed targets (its rotation takes the offsets back
// into SLAM axes). offsets_enu_m: c_t,i u_i (horizontal). buoy_enu_m: the
// buoy position with up = -depth. Needs >= 3 points with positive weights.
Similarity FitThroughTether(const Similarity& start, const std::vector<Eigen::Vector3d>& slam,
                            const std::vector<Eigen::Vector3d>& offsets_enu_m,
                            const std::vector<Eigen::Vector3d>& buoy_enu_m, const std::vector<double>& weights);

}  // namespace seamap
