#pragma once
// The checkpoint tables of an MBTiles file, and the undo journal behind them:
//   seamap_checkpoint (layer, progress, frames_from, track_from)   one row per layer
//   seamap_resume     (layer, kind, zoom_level, tile_column, tile_row, data)
//   seamap_undo       (layer, zoom_level, tile_column, tile_row, tile_data)
//   seamap_start      (layer, frames_from, track_from)               an append's start
//   seamap_start_undo (layer, zoom_level, tile_column, tile_row, tile_data)
// Once a layer has a checkpoint, the first write of each tile after it first
// copies the tile's version at the checkpoint (NULL: there was none) into
// seamap_undo, in the same transaction as the write. Every commit, whenever
// it happens, therefore holds the checkpoint plus what it takes to return to
// it: a build may commit as often as its readers need, and a checkpoint
// costs only the builder's state. Layer "" is the main tiles table; layer
// NAME the table tiles_NAME. A checkpoint with keep_start also starts a
// second journal, seamap_start_undo, of the versions before the build, which
// later checkpoints do not clear: RollBackToStart returns to them until Drop.
// Called with the store's lock held, inside its
// write transaction for the writing calls.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

#include "core/tiles/store_checkpoint.h"

struct sqlite3;
struct sqlite3_stmt;

namespace seamap {

class MBTilesJournal {
 public:
  explicit MBTilesJournal(sqlite3* db) : db_(db) {}
  ~MBTilesJournal();
  MBTilesJournal(const MBTilesJournal&) = delete;
  MBTilesJournal& operator=(const MBTilesJournal&) = delete;

  static void CreateTables(sqlite3* db);

  // A tile of the layer is about to be written.
  void BeforeTileWrite(const std::string& layer, const TileId& id);
  void Write(const std::string& layer, const CheckpointUpdate& update);
  std::optional<StoredCheckpoint> Read(const std::string& layer) const;
  std::optional<std::vector<uint8_t>> ReadBlob(const std::string& layer, int kind, const TileId& id) const;
  void RollBack(const std::string& layer);
  // False when the layer keeps no start (not an append, or a map from before).
  bool RollBackToStart(const std::string& layer);
  void Drop(const std::string& layer);

 private:
  static std::string TableOf(const std::string& layer) { return layer.empty() ? "tiles" : "tiles_" + layer; }
  void Run(const std::string& sql, const std::string& layer) const;  // one statement, ?1 = layer
  // Copies the tile's present version into `undo` (seamap_undo or
  // seamap_start_undo) unless it holds one already.
  void Keep(const std::string& undo, std::map<std::string, sqlite3_stmt*>& statements, const std::string& layer,
            const TileId& id);
  bool KeepsStart(const std::string& layer);
  void Restore(const std::string& undo, const std::string& layer, int64_t frames_from, int64_t track_from);
  [[noreturn]] void Fail(const std::string& what) const;

  sqlite3* db_;
  std::set<std::string> journaling_;  // layers with a checkpoint written or rolled back to by this process
  std::map<std::string, std::unordered_set<TileId, TileIdHash>> journaled_;  // since the checkpoint
  std::map<std::string, sqlite3_stmt*> keep_;                                // per layer: copy into seamap_undo
  std::map<std::string, bool> keeps_start_;  // per layer: has a seamap_start row (read once)
  std::map<std::string, std::unordered_set<TileId, TileIdHash>> start_journaled_;
  std::map<std::string, sqlite3_stmt*> keep_start_;  // per layer: copy into seamap_start_undo
};

}  // namespace seamap
