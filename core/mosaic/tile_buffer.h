#pragma once
// The base-zoom tiles being painted, in RAM, and when each is finished. A
// tile is finished (written once) when `linger_frames` frames in a row have
// missed it (the seed paper's rule for linger 1), unless the forecast says a
// frame soon to come will be over it again; and, past the buffer's memory
// budget, the least recently painted tiles are finished first. A tile that
// is painted again after it was finished (a live replay, a survey line
// returning later than the look-ahead, the memory budget, --append) is read
// back and blended with the weights it had, kept for recently finished tiles
// within their own budget: counting the earlier line as a single frame would
// show a seam along its edge.
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "core/geo/web_mercator.h"
#include "core/mosaic/tile_accumulator.h"
#include "core/mosaic/tile_forecast.h"
#include "core/mosaic/warped_frame.h"

namespace seamap {

struct TileBufferOptions {
  int zoom = 0, tile_size = 256, channels = 1;
  int linger_frames = 1;
  int lookahead_frames = 0;           // how far ahead the forecast is heeded (0: not at all)
  size_t memory_bytes = 0;            // tiles being painted
  size_t finished_weights_bytes = 0;  // weights of finished tiles, for painting them again
};

class TileBuffer {
 public:
  // finished(id, tile): a tile is finished (CV_8UC2 / CV_8UC4 with alpha).
  // read_back(id): the latest finished version of a tile with alpha, or an empty Mat.
  using Finished = std::function<void(const TileId&, const cv::Mat&)>;
  using ReadBack = std::function<cv::Mat(const TileId&)>;
  TileBuffer(const TileBufferOptions& options, const TileForecast* forecast, Finished finished, ReadBack read_back);

  // Blends a frame, the `frame_number`-th painted or passed, into the tiles
  // it paints. The tiles it is over but leaves to its neighbours stay too
  // (finishing them now would only read them back a frame later).
  void Paint(const WarpedFrame& frame, int frame_number);
  // Finishes the tiles whose time has come after frame `frame_number`
  // (acquisition index `frame_index`), in tile order.
  void FinishDue(int frame_number, int frame_index);
  void FinishAll();
  // The unfinished tiles as painted so far (a live view), in no particular order.
  void ForEachUnfinished(const std::function<void(const TileId&, const cv::Mat&)>& visit) const;

  int64_t readbacks() const { return readbacks_; }
  size_t bytes() const { return bytes_; }

  // Checkpoints (core/mosaic/build_checkpointer.h): the tiles and kept
  // weights that changed since the last call, each once; whether each is
  // still there says whether to save or forget it.
  struct Changes {
    std::vector<TileId> tiles, kept;
  };
  Changes TakeChanges();
  const TileAccumulator* Unfinished(const TileId& id) const;  // null when not in the buffer
  std::vector<std::pair<TileId, int>> LastFrames() const;     // every unfinished tile, in tile order
  // Kept weights, oldest first, with their stamps; Kept: null when not kept,
  // an empty Mat when they were not saved at a checkpoint (see RestoreKept).
  std::vector<std::pair<TileId, uint64_t>> KeptOrder() const;
  const cv::Mat* Kept(const TileId& id) const;
  // Back to a checkpoint's state, on an empty buffer. Kept weights given as
  // an empty Mat still count against the budget (so the same ones are
  // dropped later); a tile painted again seeds as if they were unknown.
  void RestoreTile(const TileId& id, int last_frame, const cv::Mat& sums, const cv::Mat& weight_sums);
  void RestoreKept(const TileId& id, uint64_t stamp, cv::Mat weights);
  void RestoreReadbacks(int64_t readbacks) { readbacks_ = readbacks; }

 private:
  struct Slot {
    std::unique_ptr<TileAccumulator> accumulator;
    int last_frame = 0;
  };
  void Touch(const WarpedFrame& frame, int frame_number);  // the tiles under its box stay
  Slot& Open(const TileId& id);
  void Finish(const TileId& id);
  void KeepWeights(const TileId& id, cv::Mat weights, size_t bytes);

  TileBufferOptions options_;
  const TileForecast* forecast_;
  Finished finished_;
  ReadBack read_back_;
  std::unordered_map<TileId, Slot, TileIdHash> tiles_;
  size_t bytes_ = 0;
  int64_t readbacks_ = 0;
  // Weights of finished tiles (TileAccumulator::Weights), oldest dropped first.
  struct KeptWeights {
    cv::Mat weights;
    uint64_t stamp;  // which entry of kept_order_ is this one's
    size_t bytes;    // of the weights, even when not restored
  };
  std::unordered_map<TileId, KeptWeights, TileIdHash> kept_;
  std::deque<std::pair<TileId, uint64_t>> kept_order_;
  uint64_t kept_stamp_ = 0;
  size_t kept_bytes_ = 0;
  std::unordered_set<TileId, TileIdHash> changed_tiles_, changed_kept_;  // since TakeChanges
};

}  // namespace seamap
