#pragma once
// What a mission keeps besides tiles: every frame with its pose and footprint
// (an index into the raw photos) and the vehicle track. Where the trajectory
// was corrected (refined or filtered), the pose a frame was placed with is the
// corrected one and the navigation's original pose is kept beside it.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/geo/lat_lon.h"

namespace seamap {

// The navigation's pose of a frame placed with a corrected one.
struct NavigatedPose {
  LatLon position;  // vehicle
  double altitude_m = 0, depth_m = 0, heading_deg = 0, pitch_deg = 0, roll_deg = 0;
};

// The navigation's position of a track point placed at a corrected one.
struct NavigatedPosition {
  LatLon position;
  double heading_deg = 0;
};

struct FrameRecord {
  int id = 0;              // frame index
  std::string image;       // file name as in the navigation
  std::string image_path;  // path used to read it
  std::optional<double> time_s;
  LatLon position;  // vehicle
  double altitude_m = 0, depth_m = 0, heading_deg = 0, pitch_deg = 0, roll_deg = 0;
  std::array<LatLon, 4> footprint{};  // image corners on the seabed (TL, TR, BR, BL)
  std::string status;                 // "used" or the rejection reason
  std::optional<NavigatedPose> nav;   // set when the frame was placed with a corrected pose
};

struct TrackPoint {
  int seq = 0;
  std::optional<double> time_s;
  LatLon position;
  double altitude_m = 0, depth_m = 0, heading_deg = 0;
  std::optional<NavigatedPosition> nav;  // set when the point is a corrected position
};

// An object on the seabed: found by a recogniser (on the map's tiles), marked
// by an operator, or located by stereo. Recogniser fields stay empty for marks.
struct Detection {
  int64_t id = 0;
  std::string class_name;
  double score = 1;
  LatLon position;  // centre
  std::string note;
  std::string source = "operator";                  // "recogniser", "operator" or "stereo"
  std::string model;                                // recogniser: model file name and content hash
  std::optional<int> level;                         // zoom of the window that gave the box
  std::vector<int> levels;                          // every zoom that saw it
  std::vector<LatLon> box;                          // ring NW, SW, SE, NE, NW (empty for a point mark)
  std::optional<std::array<double, 2>> position_m;  // [east, north] of the mission origin
  std::optional<std::array<double, 2>> size_m;      // [east-west, north-south]
  std::vector<int> frames;                          // photos that saw it, best first
  std::optional<int> frame_id;                      // the photo it was found in (frames[0])
  std::optional<double> time_s;
  std::string status;                 // "unconfirmed", "confirmed" or "rejected"; empty: by source (NormaliseDetection)
  bool truncated = false;             // only cut boxes were seen (at a window edge)
  std::string alt_class;              // a class that lost to this one at the same place
  std::optional<double> heading_deg;  // stereo: the object's x axis, clockwise from true north
  std::optional<double> depth_m;      // stereo: the object frame's origin below the surface
  std::optional<double> sigma_m;      // stereo: the position's horizontal uncertainty (1 sigma), metres
  std::string created, updated;       // ISO 8601 UTC
  int64_t seq = 0;                    // change number: grows with every change
};

// The mission's height model as stored (core/mission/mission_terrain.h
// encodes, checks and decodes it): a JSON header (geometry, datum, encoding,
// size and checksum of the cells) and the compressed cells. The stores keep
// it as they get it, one per mission.
struct TerrainBlob {
  std::string header_json;
  std::vector<uint8_t> cells;
};

// Detections stored before `model` and `status` existed kept a recogniser's
// name in `source`: moves it to `model` and sets the source kind. A missing
// status becomes "confirmed" for an operator's mark (it is their own call),
// "unconfirmed" otherwise.
void NormaliseDetection(Detection* d);
bool IsDetectionSource(const std::string& source);
// Whether every number a reader uses (score, position, box, position_m,
// size_m) is finite: a record that is not cannot be drawn, packed or exported.
bool IsFiniteDetection(const Detection& d);
bool IsDetectionStatus(const std::string& status);

// Where a mission's records are kept (TileStore::Records): in the same file or
// folder as its tiles, written in the store's open transaction (TileStore::Flush
// commits them).
class MissionRecords {
 public:
  virtual ~MissionRecords() = default;

  // Put replaces the frame with the same id / the point with the same seq.
  virtual void PutFrame(const FrameRecord& frame) = 0;
  virtual void PutTrackPoint(const TrackPoint& point) = 0;
  virtual std::vector<FrameRecord> Frames() const = 0;  // in id order
  virtual std::vector<TrackPoint> Track() const = 0;    // in seq order

  // Detections (objects and operator marks). Put inserts or replaces by id.
  virtual void PutDetection(const Detection& detection) = 0;
  virtual void DeleteDetection(int64_t id) = 0;
  virtual std::vector<Detection> Detections() const = 0;  // in id order
  // Detections() without the records that cannot be read or are not finite
  // (a recogniser before issue 33 stored inf/NaN boxes as nulls), whose ids
  // go to *unreadable: what exports and packs use, so that one such record
  // does not fail the whole map.
  virtual std::vector<Detection> ReadableDetections(std::vector<int64_t>* unreadable) const;
  // Rows the last Detections() skipped because they cannot be a detection
  // (numbers NULL or not finite, broken JSON): one bad row leaves the rest readable.
  virtual int64_t SkippedDetections() const { return 0; }

  // The height model (replaces an earlier one); none: the mission has none.
  virtual void PutTerrain(const TerrainBlob& terrain) = 0;
  virtual std::optional<TerrainBlob> Terrain() const = 0;
};

}  // namespace seamap
