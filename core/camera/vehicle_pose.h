#pragma once
// The vehicle's navigation state at the moment a frame was taken, in the
// mission's local frame (see core/geo/local_frame.h).
namespace seamap {

struct VehiclePose {
  double east_m = 0;       // local frame, metres
  double north_m = 0;      // local frame, metres
  double altitude_m = 0;   // above the seabed, > 0
  double depth_m = 0;      // below the surface, informative only
  double heading_deg = 0;  // clockwise from true north
  double pitch_deg = 0;    // bow up positive
  double roll_deg = 0;     // starboard down positive
};

}  // namespace seamap
