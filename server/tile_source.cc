#include "server/tile_source.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"
#include "core/tiles/tile_version.h"

namespace seamap::server {
namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::vector<std::string> SplitLayers(const std::map<std::string, std::string>& metadata) {
  std::vector<std::string> out;
  auto it = metadata.find("seamap_layers");
  if (it != metadata.end()) {
    std::stringstream in(it->second);
    std::string part;
    while (std::getline(in, part, ','))
      if (!part.empty()) out.push_back(part);
  }
  if (out.empty()) out.push_back("raw");
  return out;
}

}  // namespace

TileSource::TileSource(const std::string& path, int readers, size_t cache_bytes, const TileStore* live_metadata)
    : path_(path), folder_(!EndsWith(path, ".mbtiles")), live_metadata_(live_metadata), cache_cap_(cache_bytes) {
  const int n = folder_ ? 1 : std::max(1, readers);  // folder reads need no connection
  for (int i = 0; i < n; ++i) {
    auto reader = std::make_unique<Reader>();
    if (folder_) {
      std::string ext = "png";
      std::ifstream probe(path + "/metadata.json");
      if (probe) {
        try {
          ext = nlohmann::json::parse(probe).value("format", "png");
        } catch (const nlohmann::json::exception&) {
        }
      }
      reader->main = std::make_unique<FolderStore>(path, ext, FolderStore::Mode::kReadOnly);
    } else {
      reader->main = std::make_unique<MBTilesStore>(path, MBTilesStore::Mode::kReadOnly);
    }
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
  if (!IsLayer(layer)) throw std::out_of_range("no layer '" + layer + "'");
  auto store = reader->main->OpenLayer(layer);
  TileStore* raw = store.get();
  reader->layers[layer] = std::move(store);
  return raw;
}

std::optional<Tile> TileSource::Get(const std::string& layer, const TileId& id) {
  const std::string key = layer + "/" + std::to_string(id.z) + "/" + std::to_string(id.x) + "/" + std::to_string(id.y);
  if (auto hit = CacheLookup(key)) return hit;
  Reader* reader = Checkout();
  std::optional<std::vector<uint8_t>> bytes;
  try {
    bytes = StoreFor(reader, layer)->GetTile(id);
  } catch (...) {
    Return(reader);
    throw;
  }
  Return(reader);
  if (!bytes) return std::nullopt;
  Tile tile;
  auto text = std::make_shared<std::string>(bytes->begin(), bytes->end());
  tile.etag = "\"" + TileVersionHex(TileVersion(*text)) + "\"";
  tile.bytes = std::move(text);
  CacheInsert(key, tile);
  return tile;
}

std::optional<Tile> TileSource::CacheLookup(const std::string& key) {
  std::lock_guard<std::mutex> lock(cache_mutex_);
  auto it = cache_.find(key);
  if (it == cache_.end()) return std::nullopt;
  if (external_writer_ && std::chrono::steady_clock::now() - it->second.loaded > std::chrono::seconds(1)) {
    cache_bytes_ -= it->second.tile.bytes->size();
    lru_.erase(it->second.lru);
    cache_.erase(it);
    return std::nullopt;
  }
  lru_.splice(lru_.begin(), lru_, it->second.lru);
  return it->second.tile;
}

void TileSource::CacheInsert(const std::string& key, const Tile& tile) {
  if (tile.bytes->size() > cache_cap_ / 16) return;
  std::lock_guard<std::mutex> lock(cache_mutex_);
  if (cache_.count(key)) return;
  lru_.push_front(key);
  cache_[key] = {tile, std::chrono::steady_clock::now(), lru_.begin()};
  cache_bytes_ += tile.bytes->size();
  while (cache_bytes_ > cache_cap_ && !lru_.empty()) {
    auto victim = cache_.find(lru_.back());
    cache_bytes_ -= victim->second.tile.bytes->size();
    cache_.erase(victim);
    lru_.pop_back();
  }
}

void TileSource::Invalidate(const std::string& layer, const TileId& id) {
  const std::string key = layer + "/" + std::to_string(id.z) + "/" + std::to_string(id.x) + "/" + std::to_string(id.y);
  std::lock_guard<std::mutex> lock(cache_mutex_);
  auto it = cache_.find(key);
  if (it == cache_.end()) return;
  cache_bytes_ -= it->second.tile.bytes->size();
  lru_.erase(it->second.lru);
  cache_.erase(it);
}

std::map<std::string, std::string> TileSource::Metadata(const std::string& layer) {
  std::map<std::string, std::string> all;
  {  // read at most once a second: tile requests ask for the format
    std::lock_guard<std::mutex> lock(metadata_mutex_);
    if (metadata_loaded_ && std::chrono::steady_clock::now() - metadata_time_ < std::chrono::seconds(1))
      all = metadata_;
  }
  if (!all.empty()) {
  } else if (live_metadata_) {
    all = live_metadata_->Metadata();
  } else {
    Reader* reader = Checkout();
    try {
      all = reader->main->Metadata();
    } catch (...) {
      Return(reader);
      throw;
    }
    Return(reader);
  }
  {
    std::lock_guard<std::mutex> lock(metadata_mutex_);
    metadata_ = all;
    metadata_time_ = std::chrono::steady_clock::now();
    metadata_loaded_ = true;
  }
  if (layer.empty()) return all;
  if (folder_) {  // a folder layer keeps its metadata in layers/<name>/metadata.json
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
  for (const auto& [k, v] : all)
    if (k.compare(0, prefix.size(), prefix) == 0) out[k.substr(prefix.size())] = v;
  return out;
}

std::vector<std::string> TileSource::Layers() { return SplitLayers(Metadata("")); }

bool TileSource::IsLayer(const std::string& name) {
  auto layers = Layers();
  for (size_t i = 1; i < layers.size(); ++i)
    if (layers[i] == name) return true;
  return false;
}

std::string TileSource::Format() {
  auto m = Metadata("");
  auto it = m.find("format");
  return it == m.end() ? "png" : it->second;
}

}  // namespace seamap::server
