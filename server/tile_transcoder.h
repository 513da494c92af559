#pragma once
// Tiles of a lossless (PNG) map offered in a compact format for a weak link:
// /tiles/{z}/{x}/{y}.webp of a PNG mission is the PNG decoded and encoded as
// lossy WebP (alpha kept, so partly covered tiles stay transparent where they
// were). Results are kept in a small LRU keyed by the tile and the source's
// ETag, so a rewritten tile is transcoded again and an unchanged one never.
#include <cstddef>
#include <list>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>

#include "server/tile_source.h"

namespace seamap::server {

class TileTranscoder {
 public:
  explicit TileTranscoder(int webp_quality = 65, size_t cache_bytes = 32u << 20);

  // Formats a map stored as `stored` can also be served as (besides itself).
  static std::vector<std::string> OfferedFor(const std::string& stored);
  // `source` is the stored tile (its bytes and ETag). The answer's ETag is the
  // source's with the format added, so it changes whenever the source does.
  // Throws std::runtime_error when the source cannot be decoded.
  Tile Get(const std::string& layer, const TileId& id, const Tile& source, const std::string& ext);

 private:
  using Key = std::tuple<std::string, int, int, int, std::string>;  // layer, z, x, y, ext
  struct Entry {
    std::string source_etag;
    Tile tile;
    std::list<Key>::iterator lru;
  };
  int webp_quality_;
  size_t cap_;
  std::mutex mutex_;
  std::map<Key, Entry> entries_;
  std::list<Key> lru_;  // most recent first
  size_t bytes_ = 0;
};

}  // namespace seamap::server
