#pragma once
// A seabed point triangulated from the photos (several views of one feature
// with known or refined camera poses), in the mission's local frame, metres
// up (height_grid.h's datum). What the height model is fitted to.
#include <vector>

#include <Eigen/Core>

namespace seamap {

struct SeabedPoint {
  Eigen::Vector3d east_north_up_m = Eigen::Vector3d::Zero();
  double sigma_up_m = 0;  // 1-sigma of the height (from the rays' geometry and reprojection error)
  int views = 0;          // frames that saw it
};

using SeabedPoints = std::vector<SeabedPoint>;

}  // namespace seamap
