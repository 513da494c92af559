#pragma once
// Encodes tiles on the thread pool and writes them to the store, newest
// version wins, then hands them to the tile consumers. Until a tile is in the
// store its raw pixels stay in `pending_`, so reading a tile back always sees
// the latest version.
#include <atomic>
#include <cstdint>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <opencv2/core.hpp>

#include "core/geo/web_mercator.h"
#include "core/mosaic/tile_consumer.h"
#include "core/tiles/tile_codec.h"
#include "core/tiles/tile_store.h"
#include "core/util/thread_pool.h"

namespace seamap {

class TileWriter {
 public:
  // consumers: each gets every tile written (TileConsumer), after the store.
  TileWriter(TileStore* store, ThreadPool* pool, TileEncoding encoding, std::vector<TileConsumer*> consumers = {});
  ~TileWriter();

  // tile: CV_8UC2 / CV_8UC4 with alpha; takes a reference, do not modify it
  // later. final: see TileConsumer.
  void Submit(const TileId& id, const cv::Mat& tile, bool final = true);

  // The latest version of a tile (pending or stored), decoded; nullopt if none.
  std::optional<cv::Mat> Read(const TileId& id) const;
  // The same with `channels` colour channels plus alpha, to paint on: a JPEG
  // tile's pixels that show the background colour are empty again. An empty
  // Mat when there is no tile of `tile_size`.
  cv::Mat ReadToPaint(const TileId& id, int channels, int tile_size) const;

  // Waits for every submitted tile to be written, then commits the store.
  void Flush();

  // A resumed build: the counts of the build it continues, and the tiles it had written.
  void Resume(int64_t tiles_written, int64_t bytes_written, const std::vector<TileId>& stored);

  int64_t tiles_written() const { return written_; }  // store writes
  int64_t bytes_written() const { return bytes_; }
  std::map<int, int64_t> distinct_tiles_per_zoom() const;  // tiles that exist, by zoom

 private:
  struct Pending {
    cv::Mat tile;
    uint64_t version;
  };
  void Encode(TileId id, cv::Mat tile, uint64_t version, bool final);

  TileStore* store_;
  ThreadPool* pool_;
  TileEncoding encoding_;
  std::vector<TileConsumer*> consumers_;
  mutable std::mutex mutex_;
  std::unordered_map<TileId, Pending, TileIdHash> pending_;
  std::unordered_set<TileId, TileIdHash> seen_;  // every tile ever submitted
  std::vector<std::future<void>> in_flight_;
  std::vector<std::future<void>> done_;  // finished, not yet checked for errors
  uint64_t next_version_ = 1;
  std::atomic<int64_t> written_{0}, bytes_{0};
  std::mutex store_mutex_;  // orders the check-newest-then-put step
};

}  // namespace seamap
