#include "core/controllers/mission_trajectory_io.h"

#include <map>

#include "core/geo/rotation.h"
#include "core/mission/mission_metadata.h"
#include "core/util/error.h"

namespace seamap {
namespace {

VehiclePose LocalPose(const MissionPose& p, const LocalFrame& frame) {
  VehiclePose pose;
  const LocalXY xy = frame.FromLatLon(p.position);
  pose.east_m = xy.east, pose.north_m = xy.north;
  pose.altitude_m = p.altitude_m, pose.depth_m = p.depth_m;
  pose.heading_deg = p.heading_deg, pose.pitch_deg = p.pitch_deg, pose.roll_deg = p.roll_deg;
  return pose;
}

}  // namespace

std::vector<TrajectoryRow> MissionTrajectoryRows(const MissionTrajectory& trajectory, TrajectorySource source,
                                                 const LocalFrame& frame) {
  const std::vector<MissionPose> poses = trajectory.Poses(source);
  const std::vector<MissionPose> nav = trajectory.Poses(TrajectorySource::kNav);
  const bool corrected = source != TrajectorySource::kNav;
  std::vector<TrajectoryRow> rows;
  rows.reserve(poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    TrajectoryRow row{poses[i].image, poses[i].time_s, LocalPose(poses[i], frame), ""};
    // Placed where the navigation had it: the correction left this frame alone.
    if (corrected && poses[i].position.lat == nav[i].position.lat && poses[i].position.lon == nav[i].position.lon &&
        poses[i].heading_deg == nav[i].heading_deg)
      row.flags = "nav_only";
    rows.push_back(std::move(row));
  }
  return rows;
}

size_t WriteMissionTrajectory(const TileStore& store, const std::string& path, const std::string& option) {
  const MissionTrajectory trajectory = MissionTrajectory::Read(store);
  const MissionMetadata metadata = ReadMissionMetadata(store);
  if (!metadata.origin) throw InputError(path, 0, option, "the map has no origin (seamap_origin) to write x_m/y_m in");
  const std::vector<TrajectoryRow> rows =
      MissionTrajectoryRows(trajectory, trajectory.placed(), LocalFrame(*metadata.origin));
  WriteTrajectoryCsv(path, rows, LocalFrame(*metadata.origin));
  return rows.size();
}

NavSeries MissionTrajectorySeries(const MissionTrajectory& trajectory, const LocalFrame& frame,
                                  const std::string& map_path) {
  std::vector<NavRecord> records;
  for (const MissionPose& p : trajectory.Poses(trajectory.placed()))
    if (p.time_s) records.push_back({p.image, p.time_s, LocalPose(p, frame), p.frame_id + 1});
  if (records.empty())
    throw InputError(map_path, 0, "frames",
                     trajectory.empty()
                         ? "the mission has no frames: no trajectory to place anything with"
                         : "the mission's frames have no times: no trajectory to place anything at a time");
  return NavSeries(records);
}

Keyframe PoseKeyframe(double time_s, const VehiclePose& pose, int line) {
  Eigen::Matrix3d enu_from_ned;
  enu_from_ned << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  static const Eigen::Matrix3d body_from_camera = BodyFromCamera(CameraLooking::kDown);
  Keyframe k;
  k.time_s = time_s;
  k.position_slam = Eigen::Vector3d(pose.east_m, pose.north_m, -pose.depth_m);
  k.world_from_cam = Eigen::Quaterniond(enu_from_ned * NedFromBodyDeg(pose.heading_deg, pose.pitch_deg, pose.roll_deg) *
                                        body_from_camera)
                         .normalized();
  k.line = line;
  return k;
}

std::vector<Keyframe> MissionKeyframes(const TileStore& store, const std::string& map_path) {
  const LocalFrame frame(RequireMissionOrigin(ReadMissionMetadata(store), map_path));
  const MissionTrajectory trajectory = MissionTrajectory::Read(store);
  std::map<double, MissionPose> by_time;  // the last frame at a time wins, as NavSeries has it
  for (const MissionPose& p : trajectory.Poses(trajectory.placed()))
    if (p.time_s) by_time[*p.time_s] = p;
  std::vector<Keyframe> keyframes;
  for (const auto& [time_s, p] : by_time)
    keyframes.push_back(PoseKeyframe(time_s, LocalPose(p, frame), p.frame_id + 1));
  if (keyframes.size() < 2)
    throw InputError(
        map_path, 0, "frames",
        "the mission has " + std::to_string(keyframes.size()) + " frame(s) with a time: no trajectory to georeference");
  return keyframes;
}

}  // namespace seamap
