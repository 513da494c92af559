#include "core/controllers/repaint_store.h"

#include <stdexcept>

namespace seamap {

// The map's records, as if it had none yet (a builder numbers frames and
// track points after the ones it finds): frames and points painted again
// replace their own. Without `records`, nothing is written.
class RepaintStore::Records : public MissionRecords {
 public:
  Records(MissionRecords* inner, bool write) : inner_(inner), write_(write) {}
  void PutFrame(const FrameRecord& frame) override {
    if (write_) inner_->PutFrame(frame);
  }
  void PutTrackPoint(const TrackPoint& point) override {
    if (write_) inner_->PutTrackPoint(point);
  }
  std::vector<FrameRecord> Frames() const override { return {}; }
  std::vector<TrackPoint> Track() const override { return {}; }
  void PutDetection(const Detection& detection) override { inner_->PutDetection(detection); }
  void DeleteDetection(int64_t id) override { inner_->DeleteDetection(id); }
  std::vector<Detection> Detections() const override { return inner_->Detections(); }
  void PutTerrain(const TerrainBlob& terrain) override { inner_->PutTerrain(terrain); }
  std::optional<TerrainBlob> Terrain() const override { return inner_->Terrain(); }

 private:
  MissionRecords* inner_;
  bool write_;
};

RepaintStore::RepaintStore(TileStore* inner, RepaintScope scope)
    : inner_(inner), scope_(std::move(scope)), records_(std::make_unique<Records>(&inner->Records(), scope_.records)) {}

RepaintStore::~RepaintStore() = default;

void RepaintStore::PutTile(const TileId& id, const std::vector<uint8_t>& bytes) {
  if (id.z == scope_.base_zoom ? scope_.base_tiles && !scope_.base_tiles->count(id) : !scope_.overviews) return;
  inner_->PutTile(id, bytes);
  std::lock_guard<std::mutex> lock(mutex_);
  written_.insert(id);
}

std::optional<std::vector<uint8_t>> RepaintStore::GetTile(const TileId& id) const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!written_.count(id)) return std::nullopt;
  }
  return inner_->GetTile(id);
}

int64_t RepaintStore::TileCount() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int64_t>(written_.size());
}

std::vector<TileId> RepaintStore::TileIds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {written_.begin(), written_.end()};
}

TileSet RepaintStore::Written() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return written_;
}

void RepaintStore::SetMetadata(const std::string& key, const std::string& value) {
  if (scope_.records) inner_->SetMetadata(key, value);
}

std::unique_ptr<TileStore> RepaintStore::OpenLayer(const std::string&) {
  throw std::logic_error("RepaintStore: repaint each layer through its own store");
}

MissionRecords& RepaintStore::RecordsKept() {
  return *records_;
}

}  // namespace seamap
