#include "core/terrain/dvl_altitude.h"

#include <cmath>

#include <Eigen/Dense>

#include "core/geo/rotation.h"

namespace seamap {

double DvlAltitude(const HeightGridRayCaster& terrain, LocalXY position, double height_up_m, double heading_deg,
                   double pitch_deg, double roll_deg) {
  const Eigen::Matrix3d ned_from_body = NedFromBodyDeg(heading_deg, pitch_deg, roll_deg);
  const double tilt = kDvlBeamAngleDeg * M_PI / 180;
  const Eigen::Vector3d origin(position.east, position.north, height_up_m);
  double sum = 0;
  int hits = 0;
  for (int k = 0; k < 4; ++k) {
    const double azimuth = (45 + 90 * k) * M_PI / 180;
    const Eigen::Vector3d body(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
    const Eigen::Vector3d ned = ned_from_body * body;
    const Eigen::Vector3d enu(ned.y(), ned.x(), -ned.z());
    double t = 0;
    if (!terrain.Cast(origin, enu, &t)) continue;
    sum += -t * enu.z();  // the beam's vertical range
    ++hits;
  }
  return hits > 0 ? sum / hits : NAN;
}

}  // namespace seamap
