#pragma once
// Overview zooms (min_zoom .. base_zoom-1), kept in RAM: each overview tile is
// the 2x2 reduction of its four children. A child that changes is reduced
// into its quadrant of the parent at once; dirty overviews are written once
// per batch (Flush), level by level towards min_zoom. Clean tiles stay cached
// up to a memory cap, and are read back from the store when evicted.
#include <cstdint>
#include <list>
#include <unordered_map>

#include <opencv2/core.hpp>

#include "core/geo/web_mercator.h"
#include "core/mosaic/tile_writer.h"

namespace seamap {

// 2x2 reduction with alpha: colour is averaged over covered pixels only
// (alpha-weighted), alpha is the mean coverage. Input CV_8UC2 / CV_8UC4.
cv::Mat ReduceTile2x(const cv::Mat& tile);

class OverviewPyramid {
 public:
  OverviewPyramid(TileWriter* writer, int tile_size, int channels, int min_zoom, int base_zoom,
                  size_t memory_cap_bytes);

  // A tile at zoom > min_zoom changed: refresh its quadrant in the parent.
  void UpdateChild(const TileId& child, const cv::Mat& tile);

  // Writes every dirty overview, propagating changes down to min_zoom.
  void Flush();

  size_t Bytes() const { return bytes_; }
  int64_t DirtyCount() const;

 private:
  struct Entry {
    cv::Mat tile;
    bool dirty = false;
    std::list<TileId>::iterator lru;
  };
  Entry& Load(const TileId& id);
  void EvictClean();

  TileWriter* writer_;
  int tile_size_, channels_, min_zoom_, base_zoom_;
  size_t cap_bytes_;
  size_t bytes_ = 0;
  std::unordered_map<TileId, Entry, TileIdHash> tiles_;
  std::list<TileId> lru_;  // front = most recently used
};

}  // namespace seamap
