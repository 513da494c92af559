#pragma once
// A build's checkpoint as a tile store keeps it (TileStore::Checkpoints; the
// builder's side is core/mosaic/build_checkpointer.h). The store does not
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
  // (CheckpointStore::RollBackToStart) however many checkpoints came after.
  bool keep_start = false;
};

struct StoredCheckpoint {
  std::string progress;
  int64_t frames_from = -1, track_from = -1;
};

// Crash-safe builds, one checkpoint per layer. A store that keeps them
// (MBTiles) journals every tile written after one, so that it can return its
// tiles, frames and track to the checkpoint however it was interrupted.
// Opened read-only, it reads them and its writes throw.
class CheckpointStore {
 public:
  virtual ~CheckpointStore() = default;

  // Records the update and starts a new journal, then commits everything
  // written so far with it.
  virtual void WriteCheckpoint(const CheckpointUpdate& update) = 0;
  virtual std::optional<StoredCheckpoint> ReadCheckpoint() const = 0;
  virtual std::optional<std::vector<uint8_t>> ReadCheckpointBlob(int kind, const TileId& id) const = 0;
  // Back to the checkpoint: tiles written since get their earlier version
  // (or go), newer frames and track points go; commits. Nothing without one.
  virtual void RollBackToCheckpoint() = 0;
  // Back to before the build whose first checkpoint had keep_start (a failed
  // --append), however many checkpoints came since: tiles, frames, track;
  // forgets the checkpoint; commits. False when no start was kept.
  virtual bool RollBackToStart() = 0;
  // The build is over: forgets the checkpoint, in the open transaction (the
  // store's Flush commits).
  virtual void DropCheckpoint() = 0;
};

}  // namespace seamap
