#include "server/tile_source.h"

#include "server/tile_transcoder.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "core/mission/mission_metadata.h"
#include "core/mission/relief_layer.h"
#include "core/tiles/tile_version.h"

namespace seamap::server {
namespace {

std::vector<std::string> SplitLayers(const std::map<std::string, std::string>& metadata) {
  return ReadMissionMetadata(metadata).LayersOrRaw();
}

}  // namespace

TileSource::TileSource(const std::string& path, int readers, size_t cache_bytes, const TileStore* live_metadata)
    : path_(path),
      folder_(!IsMBTilesPath(path)),
      live_metadata_(live_metadata),
      shard_cap_(std::max<size_t>(1, cache_bytes / kShards)),
      transcoder_(std::make_unique<TileTranscoder>()) {
  const int n = folder_ ? 1 : std::max(1, readers);  // folder reads need no connection
  for (int i = 0; i < n; ++i) {
    auto reader = std::make_unique<Reader>();
    reader->main = OpenExistingMap(path, /*writable=*/false);
    free_.push_back(reader.get());
    readers_.push_back(std::move(reader));
  }
}

TileSource::~TileSource() = default;

TileSource::Reader* TileSource::Checkout() {
  std::unique_lock<std::mutex> lock(pool_mutex_);
  pool_free_.wait(lock, [this] { return !free_.empty(); });
  Reader* r = free_.back();
  free_.pop_back();
  return r;
}

void TileSource::Return(Reader* reader) {
  {
    std::lock_guard<std::mutex> lock(pool_mutex_);
    free_.push_back(reader);
  }
  pool_free_.notify_one();
}

TileStore* TileSource::StoreFor(Reader* reader, const std::string& layer) {
  if (layer.empty()) return reader->main.get();
  auto it = reader->layers.find(layer);
  if (it != reader->layers.end()) return it->second.get();
  auto store = reader->main->OpenLayer(layer);
  TileStore* raw = store.get();
  reader->layers[layer] = std::move(store);
  return raw;
}

void TileSource::CheckLayer(const std::string& layer) {
  if (!layer.empty() && !IsLayer(layer)) throw std::out_of_range("no layer '" + layer + "'");
}

std::optional<Tile> TileSource::Get(const std::string& layer, const TileId& id) {
  const CacheKey key{layer, id.z, id.x, id.y};
  uint64_t generation = 0;
  if (auto hit = CacheLookup(key, &generation)) return hit;
  CheckLayer(layer);
  std::optional<std::vector<uint8_t>> bytes;
  if (folder_ && layer.empty()) {
    // A folder store reads files without shared state: no need to queue for the one reader.
    bytes = readers_.front()->main->GetTile(id);
  } else {
    Reader* reader = Checkout();
    try {
      bytes = StoreFor(reader, layer)->GetTile(id);
    } catch (...) {
      Return(reader);
      throw;
    }
    Return(reader);
  }
  if (!bytes) return std::nullopt;
  Tile tile;
  auto text = std::make_shared<std::string>(bytes->begin(), bytes->end());
  tile.etag = "\"" + TileVersionHex(TileVersion(*text)) + "\"";
  tile.bytes = std::move(text);
  CacheInsert(key, tile, generation);
  return tile;
}

TileSource::CacheShard& TileSource::ShardFor(const CacheKey& key) {
  return shards_[CacheKeyHash()(key) % kShards];
}

std::optional<Tile> TileSource::CacheLookup(const CacheKey& key, uint64_t* generation) {
  CacheShard& shard = ShardFor(key);
  std::lock_guard<std::mutex> lock(shard.mutex);
  *generation = shard.generation;
  auto it = shard.entries.find(key);
  if (it == shard.entries.end()) return std::nullopt;
  if (external_writer_ && std::chrono::steady_clock::now() - it->second.loaded > std::chrono::seconds(1)) {
    shard.bytes -= it->second.tile.bytes->size();
    shard.lru.erase(it->second.lru);
    shard.entries.erase(it);
    return std::nullopt;
  }
  shard.lru.splice(shard.lru.begin(), shard.lru, it->second.lru);
  return it->second.tile;
}

void TileSource::CacheInsert(const CacheKey& key, const Tile& tile, uint64_t generation) {
  if (tile.bytes->size() > shard_cap_ / 4) return;
  CacheShard& shard = ShardFor(key);
  std::lock_guard<std::mutex> lock(shard.mutex);
  if (shard.generation != generation || shard.entries.count(key)) return;
  shard.lru.push_front(key);
  shard.entries[key] = {tile, std::chrono::steady_clock::now(), shard.lru.begin()};
  shard.bytes += tile.bytes->size();
  while (shard.bytes > shard_cap_ && !shard.lru.empty()) {
    auto victim = shard.entries.find(shard.lru.back());
    shard.bytes -= victim->second.tile.bytes->size();
    shard.entries.erase(victim);
    shard.lru.pop_back();
  }
}

void TileSource::Invalidate(const std::string& layer, const TileId& id) {
  const CacheKey key{layer, id.z, id.x, id.y};
  CacheShard& shard = ShardFor(key);
  std::lock_guard<std::mutex> lock(shard.mutex);
  ++shard.generation;
  auto it = shard.entries.find(key);
  if (it == shard.entries.end()) return;
  shard.bytes -= it->second.tile.bytes->size();
  shard.lru.erase(it->second.lru);
  shard.entries.erase(it);
}

std::shared_ptr<const TileSource::MetadataSnapshot> TileSource::Snapshot() {
  auto snapshot = std::atomic_load(&snapshot_);
  const auto now = std::chrono::steady_clock::now();
  if (snapshot && now - snapshot->read < std::chrono::seconds(1)) return snapshot;
  std::lock_guard<std::mutex> lock(refresh_mutex_);  // one thread reads, the others wait for it
  snapshot = std::atomic_load(&snapshot_);
  if (snapshot && now - snapshot->read < std::chrono::seconds(1)) return snapshot;
  auto fresh = std::make_shared<MetadataSnapshot>();
  if (live_metadata_) {
    fresh->all = live_metadata_->Metadata();
  } else {
    Reader* reader = Checkout();
    try {
      fresh->all = reader->main->Metadata();
    } catch (...) {
      Return(reader);
      throw;
    }
    Return(reader);
  }
  auto format = fresh->all.find("format");
  fresh->format = format == fresh->all.end() ? "png" : format->second;
  fresh->layers = SplitLayers(fresh->all);
  fresh->read = std::chrono::steady_clock::now();
  std::atomic_store(&snapshot_, std::shared_ptr<const MetadataSnapshot>(fresh));
  return fresh;
}

std::map<std::string, std::string> TileSource::Metadata(const std::string& layer) {
  auto snapshot = Snapshot();
  if (layer.empty()) return snapshot->all;
  if (folder_) {  // a folder layer keeps its metadata in layers/<name>/metadata.json
    CheckLayer(layer);
    Reader* reader = Checkout();
    std::map<std::string, std::string> out;
    try {
      out = StoreFor(reader, layer)->Metadata();
    } catch (...) {
      Return(reader);
      throw;
    }
    Return(reader);
    return out;
  }
  std::map<std::string, std::string> out;
  const std::string prefix = "layer." + layer + ".";
  for (const auto& [k, v] : snapshot->all)
    if (k.compare(0, prefix.size(), prefix) == 0) out[k.substr(prefix.size())] = v;
  return out;
}

std::vector<std::string> TileSource::Layers() {
  return Snapshot()->layers;
}

bool TileSource::IsLayer(const std::string& name) {
  auto snapshot = Snapshot();
  for (size_t i = 1; i < snapshot->layers.size(); ++i)
    if (snapshot->layers[i] == name) return true;
  // The height model's relief layer, an overlay rather than a photo layer (not in Layers()).
  return name == kReliefLayer && snapshot->all.count(kReliefKey) > 0;
}

std::string TileSource::Format() {
  return Snapshot()->format;
}

std::vector<std::string> TileSource::Formats() {
  return TileTranscoder::OfferedFor(Format());
}

std::optional<Tile> TileSource::GetAs(const std::string& layer, const TileId& id, const std::string& ext) {
  const auto offered = Formats();
  if (std::find(offered.begin(), offered.end(), ext) == offered.end())
    throw std::invalid_argument("this mission's tiles are not offered as ." + ext);
  auto source = Get(layer, id);
  if (!source || ext == offered.front()) return source;
  return transcoder_->Get(layer, id, *source, ext);
}

}  // namespace seamap::server
