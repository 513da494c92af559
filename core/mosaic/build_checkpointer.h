#pragma once
// A build's checkpoints: what a build killed at any moment needs to continue
// exactly where its last checkpoint left it (seamap build --resume).
//
// Frames committed so far have contributions that exist only in RAM: the
// tile buffer keeps unfinished tiles for a long time (the look-ahead keeps a
// tile a later survey line returns to). A checkpoint saves, with the
// builder's counters, every unfinished tile's running sums as they are (32-bit
// floats, so a resumed tile blends on bit for bit), the weights kept for
// finished tiles that a later frame will paint again, and which tiles were
// last touched when. Only what changed since the previous checkpoint is
// written; the store journals tile writes in between (CheckpointStore), so the
// checkpoint and the tiles, frames and track it goes with always agree.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/geo/web_mercator.h"
#include "core/mosaic/tile_accumulator.h"
#include "core/mosaic/tile_buffer.h"
#include "core/mosaic/tile_forecast.h"
#include "core/tiles/store_checkpoint.h"
#include "core/util/thread_pool.h"

namespace seamap {

// The builder's counters at a checkpoint (JSON in the store).
struct BuildProgress {
  int frame_index = -1;     // acquisition index of the last frame consumed (-1: none yet)
  int handover_index = -1;  // the last consumed frame that reached the warp: the next one's handover partner
  int frames_total = 0;     // frames in the survey being built
  int consumed = 0;         // frames consumed (the tile buffer's frame numbers)
  int frame_id_offset = 0;  // MissionRecorder: frame ids and track seqs
  int track_seq = 0;
  int frames_used = 0;
  int64_t tiles_written = 0, tile_bytes = 0, readbacks = 0;
  std::string previous_state;                     // the map's state before this build began ("" for a new map)
  std::string command;                            // the build's command line ("": unknown); --resume goes on with it
  nlohmann::json settings;                        // what shapes the tiles; a resumed build must use the same
  std::vector<std::pair<TileId, int>> tiles;      // unfinished, with the frame number that last touched each
  std::vector<std::pair<TileId, uint64_t>> kept;  // kept weights of finished tiles, oldest first

  nlohmann::json ToJson() const;
  // Throws std::runtime_error when the text is not a checkpoint's.
  static BuildProgress FromJson(const std::string& text);
};

// Blobs: a tile's running sums, or a finished tile's 16-bit weights; byte
// planes through deflate. Decoding throws std::runtime_error when damaged.
std::vector<uint8_t> PackSums(const TileAccumulator& tile);
std::pair<cv::Mat, cv::Mat> UnpackSums(const std::vector<uint8_t>& blob, int tile_size, int channels);
std::vector<uint8_t> PackWeights(const cv::Mat& weights);
cv::Mat UnpackWeights(const std::vector<uint8_t>& blob, int tile_size);

class BuildCheckpointer {
 public:
  BuildCheckpointer(CheckpointStore* store, TileBuffer* buffer, const TileForecast* forecast, ThreadPool* pool,
                    int tile_size, int channels);

  // Saves the buffer's changes since the last call with `progress` (its
  // tiles and kept lists are filled here) and commits the store with them.
  // frames_from / track_from: see CheckpointUpdate. Call between frames,
  // with every finished tile written.
  // keep_start: see CheckpointUpdate.
  void Write(BuildProgress progress, int64_t frames_from, int64_t track_from, bool keep_start = false);
  // The store's checkpoint, if it has one.
  std::optional<BuildProgress> Read() const;
  // Fills the (empty) buffer from the store's checkpoint `progress`.
  void Restore(const BuildProgress& progress);

 private:
  CheckpointStore* store_;
  TileBuffer* buffer_;
  const TileForecast* forecast_;
  ThreadPool* pool_;
  int tile_size_, channels_;
};

}  // namespace seamap
