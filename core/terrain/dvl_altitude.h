#pragma once
// The altitude a Doppler velocity log reports over a rugged seabed: the mean
// vertical range of its four Janus beams, 30 deg off the instrument's axis at
// 45, 135, 225 and 315 deg from the bow, tilted with the vehicle's attitude
// and cast onto the height model (a 4-beam DVL's usual bottom-track
// altitude). Over a flat seabed it equals the vertical distance to it, at
// any pitch and roll; over relief it averages the seabed within about
// altitude x tan 30 deg of the point below. The simulator writes it as
// nav.csv's altitude_m; a refinement can predict the same measurement from
// an estimated height model.
#include "core/geo/local_frame.h"
#include "core/terrain/height_grid_ray.h"

namespace seamap {

constexpr double kDvlBeamAngleDeg = 30;

// `position`, `height_up_m`: the DVL in local metres (height up, the grid's
// datum); attitude in degrees (core/geo/rotation.h). Beams that miss the
// grid are left out; NaN when all four miss.
double DvlAltitude(const HeightGridRayCaster& terrain, LocalXY position, double height_up_m, double heading_deg,
                   double pitch_deg, double roll_deg);

}  // namespace seamap
