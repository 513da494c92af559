#pragma once
// What a mission keeps besides its tiles: every frame with the pose it was
// placed with and its footprint (the map stays an index into the raw
// photos), the vehicle's track, and the map's metadata and build state.
// A frame placed with a corrected pose (FrameSpec::nav_pose set) keeps the
// navigation's pose too, in its record and its track point.
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/geo/local_frame.h"
#include "core/geo/web_mercator.h"
#include "core/mosaic/frame_pipeline.h"
#include "core/tiles/mission_records.h"
#include "core/tiles/tile_store.h"

namespace seamap {

// The map's description, written with its state.
struct MapDescription {
  std::string name, attribution, format;  // format: the tiles' extension
  int tile_size = 256, channels = 1, min_zoom = 0, base_zoom = 0;
  double gsd_m = 0;
};

class MissionRecorder {
 public:
  // Continues a stored mission (--append): frame ids and track points
  // follow the stored ones instead of replacing them.
  MissionRecorder(TileStore* store, const LocalFrame& frame, MapDescription description);

  // Stores a frame that went through the pipeline and its track point.
  std::pair<FrameRecord, TrackPoint> Record(const PlacedFrame& frame);
  // Metadata: the description, the survey's bounds so far, the frame
  // counts and the state ("building" or "complete").
  void WriteState(const std::string& state, int frames_used, int frames_rejected);

  const std::optional<LatLonBounds>& bounds() const { return bounds_; }
  int frame_id_offset() const { return frame_id_offset_; }
  int next_track_seq() const { return track_seq_; }
  // Continues a build from its checkpoint (--resume): its frame ids and
  // track seqs, and the bounds of the frames it had recorded (`recorded`).
  void Resume(int frame_id_offset, int next_track_seq, const std::vector<FrameRecord>& recorded);

 private:
  TileStore* store_;
  LocalFrame frame_;
  MapDescription description_;
  void Extend(const std::array<LatLon, 4>& footprint);

  std::optional<LatLonBounds> bounds_;  // of the used frames' footprints
  int frame_id_offset_ = 0;
  int track_seq_ = 0;
};

}  // namespace seamap
