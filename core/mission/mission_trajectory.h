#pragma once
// The mission's trajectory: the poses its frames were placed with (the
// navigation as given, the navigation filter's estimate, `replay --nav-mode
// vo|ekf`, or the survey refined from the photos, `build --refine-nav`) and the
// navigation's own poses kept beside corrected ones. Stages that come after
// the build (stereo-locate, georef, --trajectory-out, GET /api/track) read it
// here, so they use what the map was painted with without estimating again.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geo/lat_lon.h"
#include "core/tiles/mission_records.h"

namespace seamap {

class TileStore;

enum class TrajectorySource { kNav, kEstimated, kRefined };

// "nav", "estimated" or "refined".
const char* TrajectorySourceName(TrajectorySource source);

// What the frames were placed with: seamap_trajectory's mode ("refine":
// refined; "vo", "ekf": estimated); a mission without one whose frames keep
// the navigation's pose beside the placed one was corrected somehow
// (estimated); otherwise the navigation as given.
TrajectorySource PlacedTrajectorySource(const std::optional<nlohmann::json>& trajectory, bool any_frame_corrected);

// One pose of the trajectory (the vehicle's), as the mission recorded it.
struct MissionPose {
  int frame_id = 0;
  std::string image;
  std::optional<double> time_s;
  LatLon position;
  double altitude_m = 0, depth_m = 0, heading_deg = 0, pitch_deg = 0, roll_deg = 0;
};

class MissionTrajectory {
 public:
  // Reads the frames and the metadata of the mission in `store`.
  static MissionTrajectory Read(const TileStore& store);
  MissionTrajectory(std::vector<FrameRecord> frames, TrajectorySource placed);

  // What the frames were placed with.
  TrajectorySource placed() const { return placed_; }
  // The mission holds this trajectory: the navigation's always, and the one its frames were placed with.
  bool Has(TrajectorySource source) const { return source == TrajectorySource::kNav || source == placed_; }
  // Sources it holds, best first ("refined, nav").
  std::string HeldText() const;
  // One pose per recorded frame, in frame order. Empty when !Has(source).
  std::vector<MissionPose> Poses(TrajectorySource source) const;
  bool empty() const { return frames_.empty(); }

 private:
  std::vector<FrameRecord> frames_;
  TrajectorySource placed_;
};

}  // namespace seamap
