#pragma once
// Tiles of a mission for the HTTP layer: an MBTiles file read through a pool
// of read-only SQLite connections (requests run in parallel; a writer in the
// same or another process does not block them, thanks to WAL), or a folder
// pyramid. Recently served tiles are kept in an LRU cache with their ETags.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/tiles/tile_store.h"

namespace seamap::server {

class TileTranscoder;

struct Tile {
  std::shared_ptr<const std::string> bytes;
  std::string etag;  // strong, quoted: "\"0123456789abcdef\""
};

class TileSource {
 public:
  // `readers`: parallel read connections for MBTiles. `live_metadata`: the
  // store a replay is writing, whose metadata is always current (may be null).
  // Throws InputError naming the path when it is not a tile map.
  TileSource(const std::string& path, int readers, size_t cache_bytes = 64u << 20,
             const TileStore* live_metadata = nullptr);
  ~TileSource();

  // `layer` "" is the main map. nullopt: the mission has no such tile.
  // Throws std::out_of_range for an unknown layer.
  std::optional<Tile> Get(const std::string& layer, const TileId& id);
  // A tile changed (the replay committed it): drop it from the cache.
  void Invalidate(const std::string& layer, const TileId& id);
  // While another process may be writing the map, cached tiles expire after a second.
  void SetExternalWriter(bool external) { external_writer_ = external; }

  std::map<std::string, std::string> Metadata(const std::string& layer);
  // Layer names as in "seamap_layers": the first is the main map, the others
  // are served under /tiles/{name}/.
  std::vector<std::string> Layers();
  std::string Format();  // tile file extension: png, jpg, webp
  // An extra layer of Layers(), or "relief" where the map has a height model's relief layer.
  bool IsLayer(const std::string& name);
  // The tile in another format than the stored one (PNG served as WebP), or
  // nullopt where the mission has no tile. Throws std::out_of_range for an
  // unknown layer, std::invalid_argument for a format not offered.
  std::optional<Tile> GetAs(const std::string& layer, const TileId& id, const std::string& ext);
  // Formats this map's tiles are served in: the stored one first.
  std::vector<std::string> Formats();

 private:
  struct Reader {
    std::unique_ptr<TileStore> main;
    std::map<std::string, std::unique_ptr<TileStore>> layers;
  };
  struct CacheKey {
    std::string layer;
    int z;
    int64_t x, y;
    bool operator==(const CacheKey& o) const { return z == o.z && x == o.x && y == o.y && layer == o.layer; }
  };
  struct CacheKeyHash {
    size_t operator()(const CacheKey& k) const {
      return std::hash<std::string>()(k.layer) ^ (size_t(k.z) * 0x9E3779B97F4A7C15ull) ^ size_t(k.x * 1000003 + k.y);
    }
  };
  struct CacheEntry {
    Tile tile;
    std::chrono::steady_clock::time_point loaded;
    std::list<CacheKey>::iterator lru;
  };
  // Requests of many threads meet here: shards keep them off one lock.
  struct CacheShard {
    std::mutex mutex;
    std::unordered_map<CacheKey, CacheEntry, CacheKeyHash> entries;
    std::list<CacheKey> lru;  // most recent first
    size_t bytes = 0;
    // Bumped by every Invalidate: a read that started before it must not
    // cache what it read (it may be the tile the invalidation replaced).
    uint64_t generation = 0;
  };
  // Metadata as last read, shared read-only by requests; refreshed once a second.
  struct MetadataSnapshot {
    std::map<std::string, std::string> all;
    std::string format;
    std::vector<std::string> layers;
    std::chrono::steady_clock::time_point read;
  };

  Reader* Checkout();
  void Return(Reader* reader);
  // Throws std::out_of_range for an unknown layer. Call it before Checkout():
  // it may read metadata, which needs a reader of its own (with every reader
  // checked out, it would wait forever).
  void CheckLayer(const std::string& layer);
  // `layer` must have passed CheckLayer.
  TileStore* StoreFor(Reader* reader, const std::string& layer);
  CacheShard& ShardFor(const CacheKey& key);
  // The shard's generation is returned with a miss, for CacheInsert.
  std::optional<Tile> CacheLookup(const CacheKey& key, uint64_t* generation);
  void CacheInsert(const CacheKey& key, const Tile& tile, uint64_t generation);
  std::shared_ptr<const MetadataSnapshot> Snapshot();

  std::string path_;
  bool folder_;
  const TileStore* live_metadata_;
  std::vector<std::unique_ptr<Reader>> readers_;
  std::vector<Reader*> free_;
  std::mutex pool_mutex_;
  std::condition_variable pool_free_;

  static constexpr int kShards = 16;
  CacheShard shards_[kShards];
  size_t shard_cap_;
  std::atomic<bool> external_writer_{false};

  std::unique_ptr<TileTranscoder> transcoder_;

  std::mutex refresh_mutex_;
  std::shared_ptr<const MetadataSnapshot> snapshot_;  // std::atomic_load / atomic_store
};

}  // namespace seamap::server
