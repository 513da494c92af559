#pragma once
// A buoy towed on a taut, massless tether: when the vehicle is further than
// the reach, the buoy is pulled straight towards it until the tether is just
// stretched (it moves along the tether and traces a tractrix); within the
// reach the tether is slack and the buoy stays. Used by the simulator to make
// the truth and, after a first fit, to tell where the tether ran.
#include <functional>

#include <Eigen/Core>

namespace seamap {

class TowedBuoy {
 public:
  explicit TowedBuoy(const Eigen::Vector2d& start_en_m) : position_(start_en_m) {}

  // Moves the buoy for a vehicle at `vehicle_en_m` with horizontal reach
  // `reach_m`; returns whether the tether is taut.
  bool Step(const Eigen::Vector2d& vehicle_en_m, double reach_m) {
    const Eigen::Vector2d towards = vehicle_en_m - position_;
    const double distance = towards.norm();
    if (distance <= reach_m) return false;
    position_ = vehicle_en_m - reach_m * towards / distance;
    return true;
  }
  void Drift(const Eigen::Vector2d& step_en_m) { position_ += step_en_m; }
  const Eigen::Vector2d& position() const { return position_; }

 private:
  Eigen::Vector2d position_;
};

}  // namespace seamap
