#include "core/tiles/observed_store.h"

#include "core/tiles/tile_version.h"

namespace seamap {

ObservedStore::ObservedStore(TileStore* inner, Listener listener, std::string layer)
    : inner_(inner), listener_(std::move(listener)), layer_(std::move(layer)) {}

void ObservedStore::PutTile(const TileId& id, const std::vector<uint8_t>& bytes) {
  inner_->PutTile(id, bytes);
  const uint64_t version = TileVersion(bytes);
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.push_back({id, version});
}

void ObservedStore::Flush() {
  // Take the list before flushing: a tile put during the flush may not be in it.
  std::vector<CommittedTile> done;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    done.swap(pending_);
  }
  inner_->Flush();
  if (!done.empty() && listener_) listener_(layer_, done);
}

std::unique_ptr<TileStore> ObservedStore::OpenLayer(const std::string& name) {
  auto layer = std::make_unique<ObservedStore>(nullptr, listener_, name);
  layer->owned_ = inner_->OpenLayer(name);
  layer->inner_ = layer->owned_.get();
  return layer;
}

}  // namespace seamap
