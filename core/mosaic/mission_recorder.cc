#include "core/mosaic/mission_recorder.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/mission/mission_metadata.h"

namespace seamap {
namespace {

std::string Number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

}  // namespace

MissionRecorder::MissionRecorder(TileStore* store, const LocalFrame& frame, MapDescription description)
    : store_(store), frame_(frame), description_(std::move(description)) {
  for (const FrameRecord& f : store_->Records().Frames()) frame_id_offset_ = std::max(frame_id_offset_, f.id + 1);
  for (const TrackPoint& p : store_->Records().Track()) track_seq_ = std::max(track_seq_, p.seq + 1);
}

std::pair<FrameRecord, TrackPoint> MissionRecorder::Record(const PlacedFrame& p) {
  const VehiclePose& pose = p.spec.pose;
  FrameRecord record;
  record.id = frame_id_offset_ + p.spec.index;
  record.image = p.spec.image;
  record.image_path = p.spec.image_path;
  record.time_s = p.spec.time_s;
  record.position = frame_.ToLatLon({pose.east_m, pose.north_m});
  record.altitude_m = pose.altitude_m;
  record.depth_m = pose.depth_m;
  record.heading_deg = pose.heading_deg;
  record.pitch_deg = pose.pitch_deg;
  record.roll_deg = pose.roll_deg;
  if (p.footprint) record.footprint = *p.footprint;
  record.status = p.warped ? "used" : p.reject_reason;
  if (p.warped) Extend(*p.footprint);
  if (p.spec.nav_pose) {
    const VehiclePose& nav = *p.spec.nav_pose;  // through the same local frame as the placed pose
    NavigatedPose& n = record.nav.emplace();
    n.position = frame_.ToLatLon({nav.east_m, nav.north_m});
    n.altitude_m = nav.altitude_m;
    n.depth_m = nav.depth_m;
    n.heading_deg = nav.heading_deg;
    n.pitch_deg = nav.pitch_deg;
    n.roll_deg = nav.roll_deg;
  }
  store_->Records().PutFrame(record);

  TrackPoint point;
  point.seq = track_seq_++;
  point.time_s = p.spec.time_s;
  point.position = record.position;
  point.altitude_m = record.altitude_m;
  point.depth_m = record.depth_m;
  point.heading_deg = record.heading_deg;
  if (record.nav) point.nav = NavigatedPosition{record.nav->position, record.nav->heading_deg};
  store_->Records().PutTrackPoint(point);
  return {record, point};
}

void MissionRecorder::Extend(const std::array<LatLon, 4>& footprint) {
  LatLonBounds b = bounds_.value_or(LatLonBounds{540, 90, -540, -90});
  for (const auto& c : footprint) {
    // Around the origin's meridian: a survey across the antimeridian has
    // bounds past +-180 (east > west), not the whole world.
    const double lon = frame_.origin().lon + std::remainder(c.lon - frame_.origin().lon, 360.0);
    b.west = std::min(b.west, lon);
    b.east = std::max(b.east, lon);
    b.south = std::min(b.south, c.lat);
    b.north = std::max(b.north, c.lat);
  }
  bounds_ = b;
}

void MissionRecorder::Resume(int frame_id_offset, int next_track_seq, const std::vector<FrameRecord>& recorded) {
  frame_id_offset_ = frame_id_offset;
  track_seq_ = next_track_seq;
  bounds_.reset();
  for (const FrameRecord& f : recorded)
    if (f.status == "used") Extend(f.footprint);
}

void MissionRecorder::WriteState(const std::string& state, int frames_used, int frames_rejected) {
  const MapDescription& d = description_;
  store_->SetMetadata("name", d.name);
  store_->SetMetadata("format", d.format);
  store_->SetMetadata("type", "overlay");
  store_->SetMetadata("version", "1");
  store_->SetMetadata("description", "Seabed photo map built by SeaMap");
  store_->SetMetadata("attribution", d.attribution);
  store_->SetMetadata("minzoom", std::to_string(d.min_zoom));
  store_->SetMetadata("maxzoom", std::to_string(d.base_zoom));
  MissionMetadata mission;
  mission.tile_size_px = d.tile_size;
  mission.gsd_m = d.gsd_m;
  mission.channels = d.channels;
  mission.origin = frame_.origin();
  mission.state = state;
  mission.frames_used = frames_used;
  mission.frames_rejected = frames_rejected;
  WriteMissionMetadata(store_, mission);
  if (bounds_) {
    const LatLonBounds& b = *bounds_;
    store_->SetMetadata("bounds",
                        Number(b.west) + "," + Number(b.south) + "," + Number(b.east) + "," + Number(b.north));
    const int centre_zoom = std::max(d.min_zoom, std::min(d.base_zoom, d.min_zoom + 2));
    const double centre_lon = std::remainder((b.west + b.east) / 2, 360.0);
    store_->SetMetadata("center",
                        Number(centre_lon) + "," + Number((b.south + b.north) / 2) + "," + std::to_string(centre_zoom));
  }
}

}  // namespace seamap
