#pragma once
// A tile layer's view of its mission's records (TileStore::Records of a layer
// from OpenLayer): it reads the mission's frames, track, detections and
// height model and stores detections and the height model in them; frames and track points written through a layer
// are dropped, because the main map's builder records them (a layer built
// beside it would record every frame twice).
#include "core/tiles/mission_records.h"

namespace seamap {

class LayerRecords final : public MissionRecords {
 public:
  // `mission` must outlive this view.
  explicit LayerRecords(MissionRecords* mission) : mission_(mission) {}

  void PutFrame(const FrameRecord&) override {}
  void PutTrackPoint(const TrackPoint&) override {}
  std::vector<FrameRecord> Frames() const override { return mission_->Frames(); }
  std::vector<TrackPoint> Track() const override { return mission_->Track(); }
  void PutDetection(const Detection& d) override { mission_->PutDetection(d); }
  void DeleteDetection(int64_t id) override { mission_->DeleteDetection(id); }
  std::vector<Detection> Detections() const override { return mission_->Detections(); }
  std::vector<Detection> ReadableDetections(std::vector<int64_t>* unreadable) const override {
    return mission_->ReadableDetections(unreadable);
  }
  int64_t SkippedDetections() const override { return mission_->SkippedDetections(); }
  void PutTerrain(const TerrainBlob& t) override { mission_->PutTerrain(t); }
  std::optional<TerrainBlob> Terrain() const override { return mission_->Terrain(); }

 private:
  MissionRecords* mission_;
};

}  // namespace seamap
