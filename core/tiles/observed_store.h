#pragma once
// A TileStore decorator that tells a listener, after each Flush, which tiles
// became visible to readers and their versions. A live server turns these
// into `tile` events: announcing a tile before its transaction commits would
// send browsers to fetch the old one. The records are the inner store's.
// It keeps no checkpoints: rolling tiles back to one would change them
// without telling the listener (a live replay writes none).
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/tiles/tile_store.h"

namespace seamap {

struct CommittedTile {
  TileId id;
  uint64_t version = 0;  // TileVersion of the bytes
};

class ObservedStore : public TileStore {
 public:
  // (layer, tiles): layer is "" for the main map, else the layer's name.
  using Listener = std::function<void(const std::string& layer, const std::vector<CommittedTile>&)>;

  // `inner` must outlive this store.
  ObservedStore(TileStore* inner, Listener listener, std::string layer = "");

  void PutTile(const TileId& id, const std::vector<uint8_t>& bytes) override;
  std::optional<std::vector<uint8_t>> GetTile(const TileId& id) const override { return inner_->GetTile(id); }
  int64_t TileCount() const override { return inner_->TileCount(); }
  std::vector<TileId> TileIds() const override { return inner_->TileIds(); }
  void SetMetadata(const std::string& key, const std::string& value) override { inner_->SetMetadata(key, value); }
  std::map<std::string, std::string> Metadata() const override { return inner_->Metadata(); }
  void Flush() override;  // flushes the inner store, then tells the listener
  std::unique_ptr<TileStore> OpenLayer(const std::string& name) override;

 private:
  MissionRecords& RecordsKept() override { return inner_->Records(); }
  CheckpointStore* CheckpointsKept() override { return nullptr; }

  TileStore* inner_;
  std::unique_ptr<TileStore> owned_;  // a layer opened through this decorator
  Listener listener_;
  std::string layer_;
  std::mutex mutex_;
  std::vector<CommittedTile> pending_;
};

}  // namespace seamap
