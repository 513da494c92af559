#include "core/mission/mission_trajectory.h"

#include <algorithm>
#include <utility>

#include "core/mission/mission_metadata.h"
#include "core/tiles/tile_store.h"

namespace seamap {

const char* TrajectorySourceName(TrajectorySource source) {
  switch (source) {
    case TrajectorySource::kRefined:
      return "refined";
    case TrajectorySource::kEstimated:
      return "estimated";
    case TrajectorySource::kNav:
      break;
  }
  return "nav";
}

TrajectorySource PlacedTrajectorySource(const std::optional<nlohmann::json>& trajectory, bool any_frame_corrected) {
  if (trajectory && trajectory->is_object() && trajectory->contains("mode") && (*trajectory)["mode"].is_string()) {
    const std::string mode = (*trajectory)["mode"];
    if (mode == "refine") return TrajectorySource::kRefined;
    if (mode == "vo" || mode == "ekf") return TrajectorySource::kEstimated;
  }
  return any_frame_corrected ? TrajectorySource::kEstimated : TrajectorySource::kNav;
}

MissionTrajectory MissionTrajectory::Read(const TileStore& store) {
  std::vector<FrameRecord> frames = store.Records().Frames();
  const bool corrected = std::any_of(frames.begin(), frames.end(), [](const FrameRecord& f) { return f.nav; });
  const TrajectorySource placed = PlacedTrajectorySource(ReadMissionMetadata(store).trajectory, corrected);
  return MissionTrajectory(std::move(frames), placed);
}

MissionTrajectory::MissionTrajectory(std::vector<FrameRecord> frames, TrajectorySource placed)
    : frames_(std::move(frames)), placed_(placed) {}

std::string MissionTrajectory::HeldText() const {
  return placed_ == TrajectorySource::kNav ? "nav" : std::string(TrajectorySourceName(placed_)) + ", nav";
}

std::vector<MissionPose> MissionTrajectory::Poses(TrajectorySource source) const {
  std::vector<MissionPose> poses;
  if (!Has(source)) return poses;
  // The navigation's pose where the frame was placed with a corrected one, the placed pose elsewhere.
  const bool nav = source == TrajectorySource::kNav;
  for (const FrameRecord& f : frames_) {
    MissionPose p;
    p.frame_id = f.id;
    p.image = f.image;
    p.time_s = f.time_s;
    if (nav && f.nav) {
      const NavigatedPose& n = *f.nav;
      p.position = n.position;
      p.altitude_m = n.altitude_m, p.depth_m = n.depth_m, p.heading_deg = n.heading_deg;
      p.pitch_deg = n.pitch_deg, p.roll_deg = n.roll_deg;
    } else {
      p.position = f.position;
      p.altitude_m = f.altitude_m, p.depth_m = f.depth_m, p.heading_deg = f.heading_deg;
      p.pitch_deg = f.pitch_deg, p.roll_deg = f.roll_deg;
    }
    poses.push_back(std::move(p));
  }
  return poses;
}

}  // namespace seamap
