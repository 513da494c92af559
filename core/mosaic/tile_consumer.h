#pragma once
// Where the map's tiles go once they are written: the store always; besides
// it, anything that wants each tile as it appears (live events, a detector
// searching finished tiles) plugs in here.
#include <cstdint>

#include <opencv2/core.hpp>

#include "core/geo/web_mercator.h"

namespace seamap {

class TileConsumer {
 public:
  virtual ~TileConsumer() = default;
  // A tile is in the store: its pixels (CV_8UC2 gray + alpha, or CV_8UC4
  // BGRA; do not modify them) and the version the store holds. `final` is
  // false for a live view of a tile still being painted (BufferSettings::
  // live_tiles), true once the tile is finished (it may still be painted
  // again later, e.g. by a survey line that returns after the look-ahead).
  // Called on a worker thread, several at once: keep it short and thread-safe.
  virtual void OnTileWritten(const TileId& id, const cv::Mat& tile, uint64_t version, bool final) = 0;
};

}  // namespace seamap
