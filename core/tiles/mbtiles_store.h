#pragma once
// MBTiles 1.3 file (SQLite): `metadata` and `tiles` (TMS rows) tables, plus
// the mission's `frames` and `track` tables in the same file (their nav_*
// columns, added later, are added to an older file opened to write and read
// as NULL from one opened read-only). Writes are
// batched in a transaction that Flush() commits (and every 500 writes).
// Checkpoints of crash-safe builds: core/tiles/mbtiles_journal.h.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "core/tiles/mbtiles_journal.h"
#include "core/tiles/tile_store.h"

struct sqlite3;
struct sqlite3_stmt;

namespace seamap {

// Keeps the mission's records and build checkpoints itself.
class MBTilesStore : public TileStore, public MissionRecords, public CheckpointStore {
 public:
  enum class Mode {
    kCreate,    // create the file if missing, or open it to continue writing
    kReadOnly,  // the file must exist and hold a `tiles` table; Put* throw
  };

  // Throws InputError(path, 0, "--out", "cannot create MBTiles file: ...") in
  // kCreate mode, InputError(path, 0, "", "cannot open MBTiles file: ...") in
  // kReadOnly mode.
  explicit MBTilesStore(const std::string& path, Mode mode = Mode::kCreate);
  ~MBTilesStore() override;  // commits pending writes
  MBTilesStore(const MBTilesStore&) = delete;
  MBTilesStore& operator=(const MBTilesStore&) = delete;

  void PutTile(const TileId& id, const std::vector<uint8_t>& bytes) override;
  std::optional<std::vector<uint8_t>> GetTile(const TileId& id) const override;
  int64_t TileCount() const override;
  std::vector<TileId> TileIds() const override;

  void SetMetadata(const std::string& key, const std::string& value) override;
  std::map<std::string, std::string> Metadata() const override;

  void PutFrame(const FrameRecord& frame) override;
  void PutTrackPoint(const TrackPoint& point) override;
  std::vector<FrameRecord> Frames() const override;
  std::vector<TrackPoint> Track() const override;
  void PutDetection(const Detection& detection) override;
  void DeleteDetection(int64_t id) override;
  std::vector<Detection> Detections() const override;
  std::vector<Detection> ReadableDetections(std::vector<int64_t>* unreadable) const override;
  int64_t SkippedDetections() const override { return skipped_detections_; }
  // Table `terrain` (one row: header text, cells blob), made by the first PutTerrain.
  void PutTerrain(const TerrainBlob& terrain) override;
  std::optional<TerrainBlob> Terrain() const override;

  void Flush() override;
  std::unique_ptr<TileStore> OpenLayer(const std::string& name) override;

  void WriteCheckpoint(const CheckpointUpdate& update) override { WriteCheckpointOf("", update); }
  std::optional<StoredCheckpoint> ReadCheckpoint() const override;
  std::optional<std::vector<uint8_t>> ReadCheckpointBlob(int kind, const TileId& id) const override;
  void RollBackToCheckpoint() override { RollBackOf(""); }
  bool RollBackToStart() override { return RollBackToStartOf(""); }
  void DropCheckpoint() override { DropOf(""); }

  const std::string& path() const { return path_; }

 private:
  MissionRecords& RecordsKept() override { return *this; }
  CheckpointStore* CheckpointsKept() override { return this; }
  class Layer;
  static constexpr int kMaxPendingWrites = 500;

  // layer: "" for the main tiles table (the journal's key).
  void PutTileLocked(const std::string& layer, sqlite3_stmt* put, const TileId& id, const std::vector<uint8_t>& bytes);
  void WriteCheckpointOf(const std::string& layer, const CheckpointUpdate& update);
  void RollBackOf(const std::string& layer);
  bool RollBackToStartOf(const std::string& layer);
  void DropOf(const std::string& layer);
  std::optional<std::vector<uint8_t>> GetTileLocked(sqlite3_stmt* get, const TileId& id) const;
  int64_t CountRows(const std::string& table) const;
  std::vector<TileId> ReadTileIds(const std::string& table) const;
  // Every row of an optional table (none when it is missing), result column
  // i being columns[i] (NULL where an older file lacks it).
  template <typename Row>
  std::vector<Row> ReadRows(const std::string& table, const std::vector<std::string>& columns, const char* order,
                            const char* what, Row (*read_row)(sqlite3_stmt*)) const;

  void CreateSchema();
  sqlite3_stmt* Prepare(const char* sql) const;
  void Exec(const char* sql) const;
  [[noreturn]] void Fail(const std::string& what) const;
  // Opens a transaction if none is open; call with mutex_ held.
  void BeginWrite();
  // Counts a write and commits when the batch is full; call with mutex_ held.
  void EndWrite();
  void CommitLocked();
  // Rolls the open transaction back (back to the last commit, which is consistent).
  void AbandonLocked();

  std::string path_;
  Mode mode_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
  mutable std::atomic<int64_t> skipped_detections_{0};  // by the last Detections()
  bool opened_ = false;
  bool in_transaction_ = false;
  int pending_writes_ = 0;
  std::unique_ptr<MBTilesJournal> journal_;
  // Prepared once, reused (reset after each step).
  sqlite3_stmt* put_tile_ = nullptr;
  sqlite3_stmt* get_tile_ = nullptr;
  sqlite3_stmt* put_meta_ = nullptr;
  sqlite3_stmt* put_frame_ = nullptr;
  sqlite3_stmt* put_track_ = nullptr;
};

}  // namespace seamap
