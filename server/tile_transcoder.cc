#include "server/tile_transcoder.h"

#include <stdexcept>

#include "core/tiles/tile_codec.h"

namespace seamap::server {

TileTranscoder::TileTranscoder(int webp_quality, size_t cache_bytes) : webp_quality_(webp_quality), cap_(cache_bytes) {}

std::vector<std::string> TileTranscoder::OfferedFor(const std::string& stored) {
  if (stored == "png") return {"png", "webp"};
  return {stored};
}

Tile TileTranscoder::Get(const std::string& layer, const TileId& id, const Tile& source, const std::string& ext) {
  if (ext != "webp") throw std::invalid_argument("tiles are transcoded to webp only, not " + ext);
  const Key key{layer, id.z, id.x, id.y, ext};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = entries_.find(key);
    if (it != entries_.end() && it->second.source_etag == source.etag) {
      lru_.splice(lru_.begin(), lru_, it->second.lru);
      return it->second.tile;
    }
  }
  // Decoded and encoded outside the lock: other tiles go on being served.
  const std::vector<uint8_t> in(source.bytes->begin(), source.bytes->end());
  TileEncoding encoding;
  encoding.format = TileFormat::kWebp;
  encoding.webp_quality = webp_quality_;
  const std::vector<uint8_t> out = EncodeTile(DecodeTile(in), encoding);
  Tile tile;
  tile.bytes = std::make_shared<const std::string>(out.begin(), out.end());
  // "0123456789abcdef" -> "0123456789abcdef.webp": tied to the source's version.
  tile.etag = source.etag.substr(0, source.etag.size() - 1) + "." + ext + "\"";

  std::lock_guard<std::mutex> lock(mutex_);
  auto it = entries_.find(key);
  if (it != entries_.end()) {
    bytes_ -= it->second.tile.bytes->size();
    lru_.erase(it->second.lru);
    entries_.erase(it);
  }
  lru_.push_front(key);
  entries_[key] = {source.etag, tile, lru_.begin()};
  bytes_ += tile.bytes->size();
  while (bytes_ > cap_ && !lru_.empty()) {
    auto victim = entries_.find(lru_.back());
    bytes_ -= victim->second.tile.bytes->size();
    entries_.erase(victim);
    lru_.pop_back();
  }
  return tile;
}

}  // namespace seamap::server
