#pragma once
// A build's checkpoint as a tile store keeps it (TileStore::WriteCheckpoint;
// the builder's side is core/mosaic/build_checkpointer.h). The store does not
// read the builder's state: it keeps its progress text and blobs, and knows
// which frames and track points are newer than the checkpoint so that a
// rollback removes them with the newer tiles.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/geo/web_mercator.h"

namespace seamap {

struct CheckpointBlob {
  int kind = 0;  // the builder's: what the blob holds about tile `id`
  TileId id;
  std::vector<uint8_t> data;
};

// What changed since the layer's previous checkpoint.
struct CheckpointUpdate {
  std::string progress;  // the builder's counters (JSON text)
  // Frames with id >= frames_from and track points with seq >= track_from
  // are newer than the checkpoint (-1: this layer records none).
  int64_t frames_from = -1, track_from = -1;
  std::vector<CheckpointBlob> put;           // written or replaced
  std::vector<std::pair<int, TileId>> drop;  // (kind, id) no longer part of the state
  // The first checkpoint of a build appending to a complete map: from here
  // until the checkpoint is dropped the store also keeps every tile's version
  // from before the build, so that a failed append can return to it
  // (TileStore::RollBackToStart) however many checkpoints came after.
  bool keep_start = false;
};

struct StoredCheckpoint {
  std::string progress;
  int64_t frames_from = -1, track_from = -1;
};

}  // namespace seamap
