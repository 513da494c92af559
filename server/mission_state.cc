#include "server/mission_state.h"

#include "core/mission/mission_metadata.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/tiles/record_json.h"
#include "core/util/error.h"
#include "server/api_error.h"
#include "server/photo_preview.h"

namespace seamap::server {
namespace {

nlohmann::json OptionalNumber(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

}  // namespace

bool FootprintContains(const std::array<LatLon, 4>& fp, const LatLon& p) {
  bool inside = false;
  for (size_t i = 0, j = fp.size() - 1; i < fp.size(); j = i++) {
    const LatLon& a = fp[i];
    const LatLon& b = fp[j];
    if ((a.lat > p.lat) != (b.lat > p.lat) && p.lon < (b.lon - a.lon) * (p.lat - a.lat) / (b.lat - a.lat) + a.lon)
      inside = !inside;
  }
  return inside;
}

nlohmann::json PoseJson(const FrameRecord& f) {
  return {{"frame", f.id},
          {"lat", f.position.lat},
          {"lon", f.position.lon},
          {"heading_deg", f.heading_deg},
          {"depth_m", f.depth_m},
          {"altitude_m", f.altitude_m},
          {"time_s", OptionalNumber(f.time_s)}};
}

nlohmann::json TrackPointJson(const TrackPoint& p) {
  nlohmann::json nav = nullptr;
  if (p.nav) nav = {{"lat", p.nav->position.lat}, {"lon", p.nav->position.lon}, {"heading_deg", p.nav->heading_deg}};
  return {{"seq", p.seq},
          {"lat", p.position.lat},
          {"lon", p.position.lon},
          {"time_s", OptionalNumber(p.time_s)},
          {"nav", nav}};
}

nlohmann::json FrameJson(const FrameRecord& f) {
  const std::string base = "/api/frames/" + std::to_string(f.id);
  nlohmann::json nav = nullptr;
  if (f.nav) {
    const NavigatedPose& n = *f.nav;
    nav = {{"lat", n.position.lat}, {"lon", n.position.lon},        {"altitude_m", n.altitude_m},
           {"depth_m", n.depth_m},  {"heading_deg", n.heading_deg}, {"pitch_deg", n.pitch_deg},
           {"roll_deg", n.roll_deg}};
  }
  return {{"id", f.id},
          {"image", f.image},
          {"time_s", OptionalNumber(f.time_s)},
          {"lat", f.position.lat},
          {"lon", f.position.lon},
          {"heading_deg", f.heading_deg},
          {"pitch_deg", f.pitch_deg},
          {"roll_deg", f.roll_deg},
          {"altitude_m", f.altitude_m},
          {"depth_m", f.depth_m},
          {"status", f.status},
          {"footprint", FootprintToJson(f.footprint)},
          {"nav", nav},
          {"image_url", base + "/image"},
          {"thumb_url", base + "/image?max=256"}};
}

void MissionState::Load(const TileStore& store) {
  LoadTerrain(store);
  auto metadata = store.Metadata();
  const MissionMetadata mission = ReadMissionMetadata(metadata);
  std::vector<FrameRecord> frames = store.Records().Frames();
  std::vector<TrackPoint> track = store.Records().Track();
  std::lock_guard<std::mutex> lock(mutex_);
  if (metadata.count("name")) name_ = metadata["name"];
  if (metadata.count("format")) format_ = metadata["format"];
  // An unreadable trajectory was written by someone else: not ours to describe.
  trajectory_ = mission.trajectory.value_or(nullptr);
  if (mission.state) progress_.state = *mission.state == "complete" ? "complete" : "stopped";
  if (mission.origin) origin_ = *mission.origin;
  stored_t0_ = mission.t0;
  frames_ = std::move(frames);
  photo_folders_.clear();
  for (const FrameRecord& f : frames_) ++photo_folders_[PhotoFolderOf(f)];
  track_ = std::move(track);
  corrected_frames_ = static_cast<int>(
      std::count_if(frames_.begin(), frames_.end(), [](const FrameRecord& f) { return f.nav.has_value(); }));
  corrected_points_ = static_cast<int>(
      std::count_if(track_.begin(), track_.end(), [](const TrackPoint& p) { return p.nav.has_value(); }));
  progress_.frames_done = progress_.frames_total = static_cast<int>(frames_.size());
  progress_.frames_rejected = static_cast<int>(
      std::count_if(frames_.begin(), frames_.end(), [](const FrameRecord& f) { return f.status != "used"; }));
}

void MissionState::LoadTerrain(const TileStore& store) {
  std::shared_ptr<const TerrainQuery> query;
  std::string error, header;
  try {
    const std::optional<TerrainBlob> blob = store.Records().Terrain();
    if (blob) {
      header = blob->header_json;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (header == terrain_header_ && (terrain_ || !terrain_error_.empty())) return;  // unchanged
      }
      query = std::make_shared<const TerrainQuery>(DecodeMissionTerrain(*blob, "the mission"));
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  terrain_ = std::move(query);
  terrain_error_ = std::move(error);
  terrain_header_ = std::move(header);
}

nlohmann::json MissionState::TerrainAt(LatLon point) const {
  std::shared_ptr<const TerrainQuery> terrain;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!terrain_error_.empty()) throw ApiError(500, "the height model cannot be read: " + terrain_error_);
    terrain = terrain_;
  }
  if (!terrain) throw ApiError(404, "this mission has no height model (build it with --terrain)");
  return terrain->At(point);  // outside the lock: PROJ and sampling
}

void MissionState::SetName(const std::string& name) {
  std::lock_guard<std::mutex> lock(mutex_);
  name_ = name;
}

void MissionState::SetReplay(bool replay) {
  std::lock_guard<std::mutex> lock(mutex_);
  replay_ = replay;
}

void MissionState::SetLayers(std::vector<std::string> layers, std::string format) {
  std::lock_guard<std::mutex> lock(mutex_);
  layers_ = std::move(layers);
  format_ = std::move(format);
}

void MissionState::SetOrigin(double lat, double lon) {
  std::lock_guard<std::mutex> lock(mutex_);
  origin_ = LatLon{lat, lon};
}

void MissionState::SetProgress(const Progress& progress) {
  std::lock_guard<std::mutex> lock(mutex_);
  progress_ = progress;
  building_ = progress.state == "building";
}

void MissionState::SetAccess(bool token_required, bool writable) {
  std::lock_guard<std::mutex> lock(mutex_);
  token_required_ = token_required;
  writable_ = writable;
}

Progress MissionState::progress() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return progress_;
}

void MissionState::AddFrame(const FrameRecord& frame, const TrackPoint& point) {
  std::lock_guard<std::mutex> lock(mutex_);
  corrected_frames_ += frame.nav.has_value();
  ++photo_folders_[PhotoFolderOf(frame)];
  if (frames_.empty() || frame.id > frames_.back().id) {
    frames_.push_back(frame);
  } else {  // a frame painted again (appending to a mission) replaces its record
    auto it = std::lower_bound(frames_.begin(), frames_.end(), frame.id,
                               [](const FrameRecord& f, int v) { return f.id < v; });
    if (it != frames_.end() && it->id == frame.id) {
      corrected_frames_ -= it->nav.has_value();
      --photo_folders_[PhotoFolderOf(*it)];
      *it = frame;
    } else {
      frames_.insert(it, frame);
    }
  }
  if (track_.empty() || point.seq > track_.back().seq) {
    track_.push_back(point);
    corrected_points_ += point.nav.has_value();
  } else {  // a frame painted again at a corrected pose (replay --refine-nav) replaces its point
    auto it = std::lower_bound(track_.begin(), track_.end(), point.seq,
                               [](const TrackPoint& p, int seq) { return p.seq < seq; });
    if (it != track_.end() && it->seq == point.seq) {
      corrected_points_ += static_cast<int>(point.nav.has_value()) - static_cast<int>(it->nav.has_value());
      *it = point;
    }
  }
}

std::string MissionState::PhotoFolder() const {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::pair<const std::string, int>* best = nullptr;
  for (const auto& folder : photo_folders_)
    if (!folder.first.empty() && (!best || folder.second > best->second)) best = &folder;
  return best ? best->first : "";
}

nlohmann::json MissionState::StatusJson() const {
  std::lock_guard<std::mutex> lock(mutex_);
  nlohmann::json j = {{"name", name_},
                      {"state", progress_.state},
                      {"state_detail", progress_.state_detail},
                      {"replay", replay_},
                      {"frames_done", progress_.frames_done},
                      {"frames_total", progress_.frames_total},
                      {"frames_rejected", progress_.frames_rejected},
                      {"tiles_written", progress_.tiles_written},
                      {"frames_per_s", progress_.frames_per_s},
                      {"layers", layers_},
                      {"format", format_},
                      {"track_points", track_.size()},
                      {"token_required", token_required_},
                      {"writable", writable_},
                      {"trajectory_corrected", corrected_frames_ > 0 || corrected_points_ > 0},
                      {"corrected_frames", corrected_frames_},
                      {"trajectory", trajectory_},
                      {"buoy_fixes", buoy_track_.size()},
                      {"keyframes", keyframes_.size()}};
  j["progress"] = progress_.frames_total > 0
                      ? nlohmann::json(std::min(1.0, double(progress_.frames_done) / progress_.frames_total))
                      : nlohmann::json(nullptr);
  j["origin"] = origin_ ? nlohmann::json::array({origin_->lat, origin_->lon}) : nlohmann::json(nullptr);
  const std::optional<double> t0 = T0Locked();
  j["t0"] = t0 ? nlohmann::json(*t0) : nlohmann::json(nullptr);
  j["last_pose"] = nullptr;
  for (auto it = frames_.rbegin(); it != frames_.rend(); ++it) {
    if (it->status == "used") {
      j["last_pose"] = PoseJson(*it);
      break;
    }
  }
  return j;
}

std::optional<double> MissionState::T0() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return T0Locked();
}

std::optional<double> MissionState::T0Locked() const {
  if (stored_t0_) return stored_t0_;
  for (const FrameRecord& f : frames_)  // in id order: the first frame with a time
    if (f.time_s) return f.time_s;
  return std::nullopt;
}

bool MissionState::TrajectoryCorrected() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return corrected_frames_ > 0 || corrected_points_ > 0;
}

TrajectorySource MissionState::PlacedTrajectory() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return PlacedTrajectorySource(trajectory_.is_null() ? std::nullopt : std::optional<nlohmann::json>(trajectory_),
                                corrected_frames_ > 0 || corrected_points_ > 0);
}

std::vector<TrackPoint> MissionState::TrackFrom(int first_seq) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = std::lower_bound(track_.begin(), track_.end(), first_seq,
                             [](const TrackPoint& p, int seq) { return p.seq < seq; });
  return {it, track_.end()};
}

int MissionState::TrackSize() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return track_.empty() ? 0 : track_.back().seq + 1;
}

void MissionState::SetBuoyTrack(std::vector<TrackPoint> fixes) {
  for (size_t i = 0; i < fixes.size(); ++i) fixes[i].seq = static_cast<int>(i);
  std::lock_guard<std::mutex> lock(mutex_);
  buoy_track_ = std::move(fixes);
}

std::vector<TrackPoint> MissionState::BuoyTrackFrom(int first_seq) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (first_seq >= static_cast<int>(buoy_track_.size())) return {};
  return {buoy_track_.begin() + std::max(first_seq, 0), buoy_track_.end()};
}

int MissionState::BuoyTrackSize() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(buoy_track_.size());
}

void MissionState::SetKeyframes(std::vector<GeorefKeyframe> keyframes) {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_ = std::move(keyframes);
}

nlohmann::json MissionState::KeyframesJson() const {
  std::lock_guard<std::mutex> lock(mutex_);
  nlohmann::json features = nlohmann::json::array();
  for (const auto& k : keyframes_) {
    features.push_back({{"type", "Feature"},
                        {"geometry", {{"type", "Point"}, {"coordinates", {k.position.lon, k.position.lat}}}},
                        {"properties", {{"time_s", k.time_s}, {"good", k.good}}}});
    if (k.sigma_m > 0) features.back()["properties"]["sigma_m"] = k.sigma_m;
  }
  return {{"type", "FeatureCollection"}, {"features", features}};
}

std::vector<FrameRecord> MissionState::FramesCovering(const LatLon& p, size_t limit) const {
  std::vector<std::pair<double, const FrameRecord*>> hits;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const FrameRecord& f : frames_) {
    if (f.status != "used" || !FootprintContains(f.footprint, p)) continue;
    double clat = 0, clon = 0;
    for (const auto& c : f.footprint) {
      clat += c.lat / 4;
      clon += c.lon / 4;
    }
    const double dx = (clon - p.lon) * std::cos(p.lat * M_PI / 180), dy = clat - p.lat;
    hits.push_back({dx * dx + dy * dy, &f});
  }
  std::sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<FrameRecord> out;
  for (size_t i = 0; i < hits.size() && i < limit; ++i) out.push_back(*hits[i].second);
  return out;
}

std::vector<FrameRecord> MissionState::FramesMeeting(const LatLonBounds& b, size_t limit) const {
  std::vector<FrameRecord> out;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const FrameRecord& f : frames_) {
    if (out.size() >= limit) break;
    if (f.status != "used") continue;
    double west = 180, east = -180, south = 90, north = -90;
    for (const auto& c : f.footprint) {
      west = std::min(west, c.lon), east = std::max(east, c.lon);
      south = std::min(south, c.lat), north = std::max(north, c.lat);
    }
    if (east < b.west || west > b.east || north < b.south || south > b.north) continue;
    out.push_back(f);
  }
  return out;
}

nlohmann::json FootprintFeature(const FrameRecord& f) {
  nlohmann::json ring = nlohmann::json::array();
  for (const auto& c : f.footprint) ring.push_back({c.lon, c.lat});
  ring.push_back({f.footprint[0].lon, f.footprint[0].lat});  // GeoJSON rings are closed
  return {
      {"type", "Feature"},
      {"id", f.id},
      {"geometry", {{"type", "Polygon"}, {"coordinates", {ring}}}},
      {"properties",
       {{"id", f.id}, {"image", f.image}, {"time_s", f.time_s ? nlohmann::json(*f.time_s) : nlohmann::json(nullptr)}}}};
}

std::optional<FrameRecord> MissionState::Frame(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = std::lower_bound(frames_.begin(), frames_.end(), id, [](const FrameRecord& f, int v) { return f.id < v; });
  if (it == frames_.end() || it->id != id) return std::nullopt;
  return *it;
}

}  // namespace seamap::server
