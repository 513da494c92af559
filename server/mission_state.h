#pragma once
// What the server knows about the mission besides tiles: build progress, the
// last pose, every frame (with its seabed footprint) and the track. Held in
// memory so live events and REST answers agree; loaded from the store for a
// finished mission, appended to by a live replay. Thread-safe.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geo/web_mercator.h"

#include "core/mission/mission_trajectory.h"
#include "core/tiles/tile_store.h"
#include "server/terrain_query.h"

namespace seamap::server {

struct Progress {
  std::string state = "complete";  // "building", "complete", "stopped" or "interrupted"
  std::string state_detail;        // interrupted: what happened and the command that resumes it
  int frames_done = 0;             // frames seen (used + rejected)
  int frames_total = 0;            // 0 when unknown (a watched folder)
  int frames_rejected = 0;
  int64_t tiles_written = 0;
  double frames_per_s = 0;
};

// A SLAM keyframe georeferenced by the buoy; `good`: used in the fit.
struct GeorefKeyframe {
  double time_s = 0;
  LatLon position;
  bool good = false;
  double sigma_m = 0;  // predicted horizontal error (2D RMS, metres); 0 = unknown
};

class MissionState {
 public:
  // Frames, track, metadata and height model of a stored mission.
  void Load(const TileStore& store);
  // The height model alone (a build stored one): decoded again only when
  // the stored one changed; one that cannot be read is kept as its error.
  void LoadTerrain(const TileStore& store);
  // GET /api/terrain: the height at a point (TerrainQuery::At); ApiError 404
  // when the mission has no height model, 500 when it cannot be read.
  nlohmann::json TerrainAt(LatLon point) const;

  void SetName(const std::string& name);
  void SetReplay(bool replay);
  void SetLayers(std::vector<std::string> layers, std::string format);
  void SetOrigin(double lat, double lon);
  void SetProgress(const Progress& progress);
  // Whether writes need a token and are possible at all (for the console).
  void SetAccess(bool token_required, bool writable);
  Progress progress() const;
  // The map is still growing (cheap: asked by every tile request).
  bool building() const { return building_; }
  // A frame went through the builder; its position joins the track.
  void AddFrame(const FrameRecord& frame, const TrackPoint& point);

  // {name, state, replay, frames_done, ..., last_pose, origin, layers, format,
  //  trajectory_corrected, corrected_frames, t0}
  nlohmann::json StatusJson() const;
  // The time of the mission's first frame (metadata seamap_t0, else the first
  // frame by id with a time): modem records count tenths of a second from it.
  std::optional<double> T0() const;
  // Some frames were placed with a corrected pose (a refined or filtered
  // trajectory), the navigation's kept beside it.
  bool TrajectoryCorrected() const;
  // What the frames were placed with (core/mission/mission_trajectory.h): refined, estimated or nav.
  TrajectorySource PlacedTrajectory() const;
  // Track points with seq >= first_seq.
  std::vector<TrackPoint> TrackFrom(int first_seq) const;
  int TrackSize() const;
  // The GPS buoy's fixes (seamap serve --buoy), seq 0.. in time order.
  void SetBuoyTrack(std::vector<TrackPoint> fixes);
  std::vector<TrackPoint> BuoyTrackFrom(int first_seq) const;
  int BuoyTrackSize() const;
  // SLAM keyframes placed by the buoy (seamap georef's nav.csv, given with
  // --georef-nav): a FeatureCollection of Points with time_s, good (used
  // in the fit) and sigma_m (predicted error, when known) for /api/keyframes.
  void SetKeyframes(std::vector<GeorefKeyframe> keyframes);
  nlohmann::json KeyframesJson() const;
  // Used frames whose footprint contains the point, nearest footprint centre first.
  std::vector<FrameRecord> FramesCovering(const LatLon& point, size_t limit) const;
  std::optional<FrameRecord> Frame(int id) const;
  // The folder most frames' photos were read from (PhotoFolderOf): photos are
  // served from there only (or --images). Empty when no frame records one.
  std::string PhotoFolder() const;
  // Used frames whose footprint meets the bounds, in id order; at most `limit`.
  std::vector<FrameRecord> FramesMeeting(const LatLonBounds& bounds, size_t limit) const;

 private:
  mutable std::mutex mutex_;
  std::string name_ = "SeaMap mission";
  bool replay_ = false;
  std::vector<std::string> layers_{"raw"};
  std::string format_ = "png";
  std::optional<LatLon> origin_;
  Progress progress_;
  bool token_required_ = false, writable_ = false;
  std::atomic<bool> building_{false};
  std::vector<FrameRecord> frames_;           // in id order
  std::map<std::string, int> photo_folders_;  // PhotoFolderOf -> frames
  std::vector<TrackPoint> track_;             // in seq order
  std::vector<TrackPoint> buoy_track_;        // in seq order
  std::vector<GeorefKeyframe> keyframes_;
  int corrected_frames_ = 0;   // frames with the navigation's pose beside the placed one
  nlohmann::json trajectory_;  // how the poses were estimated (MissionMetadata::trajectory), or null
  int corrected_points_ = 0;   // track points likewise
  std::optional<double> stored_t0_;
  std::shared_ptr<const TerrainQuery> terrain_;  // null: none (or unreadable: terrain_error_)
  std::string terrain_error_;
  std::string terrain_header_;  // the stored header it was decoded from (has the cells' CRC)

  std::optional<double> T0Locked() const;
};

// Point-in-polygon (even-odd rule) on lon/lat, for footprints of a few metres.
bool FootprintContains(const std::array<LatLon, 4>& footprint, const LatLon& point);

// JSON a client gets for a frame: pose, footprint as [[lon,lat]...], image URLs,
// and `nav`, the navigation's pose {lat, lon, altitude_m, depth_m, heading_deg,
// pitch_deg, roll_deg} where the frame was placed with a corrected one (else null).
nlohmann::json FrameJson(const FrameRecord& frame);
// A frame's footprint as a GeoJSON Feature (Polygon; properties id, image,
// time_s): what a footprints layer draws, without the rest of the record.
nlohmann::json FootprintFeature(const FrameRecord& frame);
nlohmann::json PoseJson(const FrameRecord& frame);
// {seq, lat, lon, time_s, nav: {lat, lon, heading_deg} or null}: a `track` event.
nlohmann::json TrackPointJson(const TrackPoint& point);

}  // namespace seamap::server
