#pragma once
// The tether between the vehicle and its GPS buoy: its horizontal reach, the
// vehicle's position from the buoy's, how long to tow before trusting it, and
// how long a window of fixes it takes to know the towing direction well enough.
#include <Eigen/Core>

namespace seamap {

// c_t = sqrt(c^2 - d^2): 27.27 m for c = 30, d = 12.5; 0 when d = c.
// Throws std::invalid_argument for c <= 0, d < 0 or d > c.
double TetherReach(double tether_length_m, double depth_m);

// The vehicle is ahead of the buoy, which trails: p = b + c_t u, with u the
// towing direction (any length, horizontal: east, north).
Eigen::Vector2d VehicleFromBuoy(const Eigen::Vector2d& buoy_en_m, const Eigen::Vector2d& towing_direction,
                                double reach_m);

// t_c = 2 c_t / |v|: the time to travel twice the reach (the paper prints
// 2 |v| / c_t, which has units of 1/s).
double TautTime(double reach_m, double speed_mps);

// The direction error (radians) of a quadratic-in-time fit to a window of
// `window_s` seconds of fixes at `fix_rate_hz` with sigma `gps_sigma_m` per
// axis, buoy speed `speed_mps`: sigma * sqrt(12) / (|v| sqrt(f) T^1.5).
double WindowDirectionSigma(double gps_sigma_m, double speed_mps, double fix_rate_hz, double window_s);

// The shortest window whose direction error moves the vehicle sideways by at
// most max(0.5 sigma, 1 cm): c_t * sigma_theta(T) <= that; not clipped.
double DirectionWindow(double gps_sigma_m, double speed_mps, double fix_rate_hz, double reach_m);

}  // namespace seamap
