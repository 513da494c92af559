#include "core/tiles/mbtiles_journal.h"

#include <sqlite3.h>

#include <stdexcept>

namespace seamap {
namespace {

constexpr const char* kTables = R"sql(
CREATE TABLE IF NOT EXISTS seamap_checkpoint (layer text primary key, progress text, frames_from integer,
                                              track_from integer);
CREATE TABLE IF NOT EXISTS seamap_resume (layer text, kind integer, zoom_level integer, tile_column integer,
                                          tile_row integer, data blob,
                                          primary key (layer, kind, zoom_level, tile_column, tile_row));
CREATE TABLE IF NOT EXISTS seamap_undo (layer text, zoom_level integer, tile_column integer, tile_row integer,
                                        tile_data blob, primary key (layer, zoom_level, tile_column, tile_row));
CREATE TABLE IF NOT EXISTS seamap_start (layer text primary key, frames_from integer, track_from integer);
CREATE TABLE IF NOT EXISTS seamap_start_undo (layer text, zoom_level integer, tile_column integer, tile_row integer,
                                              tile_data blob, primary key (layer, zoom_level, tile_column, tile_row));
)sql";

// A statement prepared for one use, finalized whatever happens.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s_, nullptr) != SQLITE_OK) {
      sqlite3_finalize(s_);
      s_ = nullptr;
    }
  }
  ~Statement() { sqlite3_finalize(s_); }
  sqlite3_stmt* get() const { return s_; }

 private:
  sqlite3_stmt* s_ = nullptr;
};

void BindTile(sqlite3_stmt* s, int first, const TileId& id) {
  sqlite3_bind_int(s, first, id.z);
  sqlite3_bind_int(s, first + 1, id.x);
  sqlite3_bind_int(s, first + 2, id.TmsRow());
}

void BindLayer(sqlite3_stmt* s, const std::string& layer) {
  sqlite3_bind_text(s, 1, layer.c_str(), -1, SQLITE_TRANSIENT);
}

}  // namespace

MBTilesJournal::~MBTilesJournal() {
  for (auto& [layer, s] : keep_) sqlite3_finalize(s);
  for (auto& [layer, s] : keep_start_) sqlite3_finalize(s);
}

void MBTilesJournal::CreateTables(sqlite3* db) {
  if (sqlite3_exec(db, kTables, nullptr, nullptr, nullptr) != SQLITE_OK)
    throw std::runtime_error(std::string("create checkpoint tables: ") + sqlite3_errmsg(db));
}

void MBTilesJournal::Fail(const std::string& what) const {
  throw std::runtime_error(what + ": " + sqlite3_errmsg(db_));
}

void MBTilesJournal::Run(const std::string& sql, const std::string& layer) const {
  Statement s(db_, sql);
  if (!s.get()) Fail("prepare " + sql);
  if (sqlite3_bind_parameter_count(s.get()) > 0) BindLayer(s.get(), layer);
  if (sqlite3_step(s.get()) != SQLITE_DONE) Fail(sql);
}

void MBTilesJournal::BeforeTileWrite(const std::string& layer, const TileId& id) {
  if (journaling_.count(layer) && journaled_[layer].insert(id).second) {
    try {
      Keep("seamap_undo", keep_, layer, id);
    } catch (...) {
      journaled_[layer].erase(id);
      throw;
    }
  }
  if (KeepsStart(layer) && start_journaled_[layer].insert(id).second) {
    try {
      Keep("seamap_start_undo", keep_start_, layer, id);
    } catch (...) {
      start_journaled_[layer].erase(id);
      throw;
    }
  }
}

void MBTilesJournal::Keep(const std::string& undo, std::map<std::string, sqlite3_stmt*>& statements,
                          const std::string& layer, const TileId& id) {
  sqlite3_stmt*& keep = statements[layer];
  if (!keep) {
    const std::string sql = "INSERT OR IGNORE INTO " + undo +
                            " (layer, zoom_level, tile_column, tile_row, tile_data) "
                            "SELECT ?1, ?2, ?3, ?4, (SELECT tile_data FROM " +
                            TableOf(layer) + " WHERE zoom_level = ?2 AND tile_column = ?3 AND tile_row = ?4)";
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &keep, nullptr) != SQLITE_OK) Fail("prepare " + undo);
  }
  BindLayer(keep, layer);
  BindTile(keep, 2, id);
  const int rc = sqlite3_step(keep);
  sqlite3_reset(keep);
  sqlite3_clear_bindings(keep);
  if (rc != SQLITE_DONE) Fail("write " + undo);
}

// A resumed append finds its start in the file; other maps have none (or no table).
bool MBTilesJournal::KeepsStart(const std::string& layer) {
  auto it = keeps_start_.find(layer);
  if (it != keeps_start_.end()) return it->second;
  Statement s(db_, "SELECT 1 FROM seamap_start WHERE layer = ?1");
  bool keeps = false;
  if (s.get()) {
    BindLayer(s.get(), layer);
    keeps = sqlite3_step(s.get()) == SQLITE_ROW;
  }
  return keeps_start_[layer] = keeps;
}

void MBTilesJournal::Write(const std::string& layer, const CheckpointUpdate& u) {
  CreateTables(db_);  // a map made before checkpoints existed
  {
    Statement put(db_,
                  "INSERT OR REPLACE INTO seamap_resume (layer, kind, zoom_level, tile_column, tile_row, data) "
                  "VALUES (?1, ?2, ?3, ?4, ?5, ?6)");
    if (!put.get()) Fail("prepare checkpoint");
    for (const CheckpointBlob& b : u.put) {
      BindLayer(put.get(), layer);
      sqlite3_bind_int(put.get(), 2, b.kind);
      BindTile(put.get(), 3, b.id);
      sqlite3_bind_blob(put.get(), 6, b.data.data(), static_cast<int>(b.data.size()), SQLITE_STATIC);
      const int rc = sqlite3_step(put.get());
      sqlite3_reset(put.get());
      if (rc != SQLITE_DONE) Fail("write checkpoint");
    }
  }
  {
    Statement drop(db_,
                   "DELETE FROM seamap_resume WHERE layer = ?1 AND kind = ?2 AND zoom_level = ?3 AND "
                   "tile_column = ?4 AND tile_row = ?5");
    if (!drop.get()) Fail("prepare checkpoint");
    for (const auto& [kind, id] : u.drop) {
      BindLayer(drop.get(), layer);
      sqlite3_bind_int(drop.get(), 2, kind);
      BindTile(drop.get(), 3, id);
      const int rc = sqlite3_step(drop.get());
      sqlite3_reset(drop.get());
      if (rc != SQLITE_DONE) Fail("write checkpoint");
    }
  }
  Statement row(db_,
                "INSERT OR REPLACE INTO seamap_checkpoint (layer, progress, frames_from, track_from) "
                "VALUES (?1, ?2, ?3, ?4)");
  if (!row.get()) Fail("prepare checkpoint");
  BindLayer(row.get(), layer);
  sqlite3_bind_text(row.get(), 2, u.progress.c_str(), -1, SQLITE_STATIC);
  sqlite3_bind_int64(row.get(), 3, u.frames_from);
  sqlite3_bind_int64(row.get(), 4, u.track_from);
  if (sqlite3_step(row.get()) != SQLITE_DONE) Fail("write checkpoint");
  Run("DELETE FROM seamap_undo WHERE layer = ?1", layer);
  journaling_.insert(layer);
  journaled_[layer].clear();
  if (u.keep_start) {
    Run("DELETE FROM seamap_start_undo WHERE layer = ?1", layer);
    Statement start(db_, "INSERT OR REPLACE INTO seamap_start (layer, frames_from, track_from) VALUES (?1, ?2, ?3)");
    if (!start.get()) Fail("prepare start");
    BindLayer(start.get(), layer);
    sqlite3_bind_int64(start.get(), 2, u.frames_from);
    sqlite3_bind_int64(start.get(), 3, u.track_from);
    if (sqlite3_step(start.get()) != SQLITE_DONE) Fail("write start");
    keeps_start_[layer] = true;
    start_journaled_[layer].clear();
  }
}

std::optional<StoredCheckpoint> MBTilesJournal::Read(const std::string& layer) const {
  Statement s(db_, "SELECT progress, frames_from, track_from FROM seamap_checkpoint WHERE layer = ?1");
  if (!s.get()) return std::nullopt;  // no checkpoint table: a map made before they existed
  BindLayer(s.get(), layer);
  const int rc = sqlite3_step(s.get());
  if (rc == SQLITE_DONE) return std::nullopt;
  if (rc != SQLITE_ROW) Fail("read checkpoint");
  StoredCheckpoint c;
  const unsigned char* text = sqlite3_column_text(s.get(), 0);
  c.progress = text ? reinterpret_cast<const char*>(text) : "";
  c.frames_from = sqlite3_column_int64(s.get(), 1);
  c.track_from = sqlite3_column_int64(s.get(), 2);
  return c;
}

std::optional<std::vector<uint8_t>> MBTilesJournal::ReadBlob(const std::string& layer, int kind,
                                                             const TileId& id) const {
  Statement s(db_,
              "SELECT data FROM seamap_resume WHERE layer = ?1 AND kind = ?2 AND zoom_level = ?3 AND "
              "tile_column = ?4 AND tile_row = ?5");
  if (!s.get()) return std::nullopt;
  BindLayer(s.get(), layer);
  sqlite3_bind_int(s.get(), 2, kind);
  BindTile(s.get(), 3, id);
  const int rc = sqlite3_step(s.get());
  if (rc == SQLITE_DONE) return std::nullopt;
  if (rc != SQLITE_ROW) Fail("read checkpoint");
  const auto* data = static_cast<const uint8_t*>(sqlite3_column_blob(s.get(), 0));
  return std::vector<uint8_t>(data, data + sqlite3_column_bytes(s.get(), 0));
}

// Tiles written since the undo journal began get the version it kept (or
// go, where it kept none); newer frames and track points go.
void MBTilesJournal::Restore(const std::string& undo, const std::string& layer, int64_t frames_from,
                             int64_t track_from) {
  const std::string table = TableOf(layer);
  const std::string same_tile = "u.layer = ?1 AND u.zoom_level = " + table +
                                ".zoom_level AND u.tile_column = " + table + ".tile_column AND u.tile_row = " + table +
                                ".tile_row";
  Run("DELETE FROM " + table + " WHERE EXISTS (SELECT 1 FROM " + undo + " AS u WHERE " + same_tile +
          " AND u.tile_data IS NULL)",
      layer);
  Run("INSERT OR REPLACE INTO " + table +
          " (zoom_level, tile_column, tile_row, tile_data) SELECT zoom_level, tile_column, tile_row, tile_data "
          "FROM " +
          undo + " WHERE layer = ?1 AND tile_data IS NOT NULL",
      layer);
  Run("DELETE FROM " + undo + " WHERE layer = ?1", layer);
  if (layer.empty()) {  // the main layer records the mission's frames and track
    if (frames_from >= 0) Run("DELETE FROM frames WHERE id >= " + std::to_string(frames_from), layer);
    if (track_from >= 0) Run("DELETE FROM track WHERE seq >= " + std::to_string(track_from), layer);
  }
}

void MBTilesJournal::RollBack(const std::string& layer) {
  const std::optional<StoredCheckpoint> c = Read(layer);
  if (!c) return;
  Restore("seamap_undo", layer, c->frames_from, c->track_from);
  journaling_.insert(layer);
  journaled_[layer].clear();
}

bool MBTilesJournal::RollBackToStart(const std::string& layer) {
  if (!KeepsStart(layer)) return false;
  Statement s(db_, "SELECT frames_from, track_from FROM seamap_start WHERE layer = ?1");
  if (!s.get()) Fail("read start");
  BindLayer(s.get(), layer);
  if (sqlite3_step(s.get()) != SQLITE_ROW) Fail("read start");
  const int64_t frames_from = sqlite3_column_int64(s.get(), 0), track_from = sqlite3_column_int64(s.get(), 1);
  // Every tile written since the start has its version from before in
  // seamap_start_undo (kept in the transaction of its first write).
  Restore("seamap_start_undo", layer, frames_from, track_from);
  Drop(layer);
  return true;
}

void MBTilesJournal::Drop(const std::string& layer) {
  Statement probe(db_, "SELECT 1 FROM seamap_checkpoint");
  if (!probe.get()) return;  // never had one
  for (const char* table : {"seamap_resume", "seamap_undo", "seamap_checkpoint"})
    Run(std::string("DELETE FROM ") + table + " WHERE layer = ?1", layer);
  journaling_.erase(layer);
  journaled_.erase(layer);
  Statement start(db_, "SELECT 1 FROM seamap_start");
  if (!start.get()) return;  // a map from before starts were kept
  for (const char* table : {"seamap_start_undo", "seamap_start"})
    Run(std::string("DELETE FROM ") + table + " WHERE layer = ?1", layer);
  keeps_start_[layer] = false;
  start_journaled_.erase(layer);
}

}  // namespace seamap
