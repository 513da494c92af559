#include "core/tiles/mbtiles_store.h"

#include <sqlite3.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "core/tiles/record_json.h"
#include "core/tiles/sqlite_columns.h"
#include "core/util/error.h"

namespace seamap {
namespace {

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS metadata (name text, value text);
CREATE UNIQUE INDEX IF NOT EXISTS metadata_name ON metadata (name);
CREATE TABLE IF NOT EXISTS tiles (zoom_level integer, tile_column integer, tile_row integer,
                                  tile_data blob);
CREATE UNIQUE INDEX IF NOT EXISTS tile_index ON tiles (zoom_level, tile_column, tile_row);
CREATE TABLE IF NOT EXISTS frames (id integer primary key, image text, image_path text,
                                   time_s real, lat real, lon real, altitude_m real,
                                   depth_m real, heading_deg real, pitch_deg real,
                                   roll_deg real, footprint text, status text,
                                   nav_lat real, nav_lon real, nav_altitude_m real,
                                   nav_depth_m real, nav_heading_deg real, nav_pitch_deg real,
                                   nav_roll_deg real);
CREATE TABLE IF NOT EXISTS track (seq integer primary key, time_s real, lat real, lon real,
                                  altitude_m real, depth_m real, heading_deg real,
                                  nav_lat real, nav_lon real, nav_heading_deg real);
CREATE TABLE IF NOT EXISTS detections (id integer primary key, class text, score real, lat real,
                                       lon real, note text, source text, frame_id integer,
                                       time_s real, created text, updated text, seq integer);
)sql";

// The navigation's pose beside the placed one (NULL unless the trajectory was
// corrected): files written before these columns existed lack them.
const std::vector<SqlColumn> kFrameNavColumns = {
    {"nav_lat", "real"},         {"nav_lon", "real"},       {"nav_altitude_m", "real"}, {"nav_depth_m", "real"},
    {"nav_heading_deg", "real"}, {"nav_pitch_deg", "real"}, {"nav_roll_deg", "real"}};
const std::vector<SqlColumn> kTrackNavColumns = {{"nav_lat", "real"}, {"nav_lon", "real"}, {"nav_heading_deg", "real"}};
// A recogniser's fields and the review status (issue 19); arrays as JSON text.
const std::vector<SqlColumn> kDetectionObjectColumns =
    {
        {"model", "text"},       {"level", "integer"}, {"levels", "text"},       {"box", "text"},
        {"east_m", "real"},      {"north_m", "real"},  {"size_ew_m", "real"},    {"size_ns_m", "real"},
        {"frames", "text"},      {"status", "text"},   {"truncated", "integer"}, {"alt_class", "text"},
        {"heading_deg", "real"}, {"depth_m", "real"},  // a stereo location's orientation and depth (issue 20)
        {"sigma_m", "real"}};                          // and its uncertainty (issue 30)
const std::vector<std::string> kDetectionColumns = {
    "id",        "class",     "score",  "lat",    "lon",       "note",      "source",      "frame_id", "time_s",
    "created",   "updated",   "seq",    "model",  "level",     "levels",    "box",         "east_m",   "north_m",
    "size_ew_m", "size_ns_m", "frames", "status", "truncated", "alt_class", "heading_deg", "depth_m",  "sigma_m"};

// Every column in the order rows are bound and read.
const std::vector<std::string> kFrameColumns = {
    "id",      "image",          "image_path",  "time_s",          "lat",           "lon",         "altitude_m",
    "depth_m", "heading_deg",    "pitch_deg",   "roll_deg",        "footprint",     "status",      "nav_lat",
    "nav_lon", "nav_altitude_m", "nav_depth_m", "nav_heading_deg", "nav_pitch_deg", "nav_roll_deg"};
const std::vector<std::string> kTrackColumns = {"seq",     "time_s",      "lat",     "lon",     "altitude_m",
                                                "depth_m", "heading_deg", "nav_lat", "nav_lon", "nav_heading_deg"};

std::string InsertSql(const std::string& table, const std::vector<std::string>& columns) {
  std::string names, marks;
  for (const std::string& c : columns) {
    names += (names.empty() ? "" : ", ") + c;
    marks += marks.empty() ? "?" : ", ?";
  }
  return "INSERT OR REPLACE INTO " + table + " (" + names + ") VALUES (" + marks + ")";
}

// Resets a reused statement when the scope ends, whatever happens.
class StatementReset {
 public:
  explicit StatementReset(sqlite3_stmt* s) : s_(s) {}
  ~StatementReset() {
    sqlite3_reset(s_);
    sqlite3_clear_bindings(s_);
  }

 private:
  sqlite3_stmt* s_;
};

// A statement run once (reads of whole tables).
struct OneShot {
  sqlite3_stmt* s;
  ~OneShot() { sqlite3_finalize(s); }
};

void BindOptional(sqlite3_stmt* s, int col, const std::optional<double>& v) {
  if (v) {
    sqlite3_bind_double(s, col, *v);
  } else {
    sqlite3_bind_null(s, col);
  }
}

std::optional<double> ColumnOptional(sqlite3_stmt* s, int col) {
  if (sqlite3_column_type(s, col) == SQLITE_NULL) return std::nullopt;
  return sqlite3_column_double(s, col);
}

// Whether columns first..last all hold values (a nav pose is all there or absent).
bool ColumnsSet(sqlite3_stmt* s, int first, int last) {
  for (int col = first; col <= last; ++col)
    if (sqlite3_column_type(s, col) == SQLITE_NULL) return false;
  return true;
}

std::string ColumnText(sqlite3_stmt* s, int col) {
  const unsigned char* text = sqlite3_column_text(s, col);
  return text ? reinterpret_cast<const char*>(text) : "";
}

// A finite number in a column that must hold one (NULL, text or inf throw).
double ColumnNumber(sqlite3_stmt* s, int col) {
  const int type = sqlite3_column_type(s, col);
  const double v = sqlite3_column_double(s, col);
  if ((type != SQLITE_INTEGER && type != SQLITE_FLOAT) || !std::isfinite(v))
    throw std::invalid_argument("not a finite number");
  return v;
}

// An optional number: NULL is none, anything else must be finite.
std::optional<double> ColumnFiniteOptional(sqlite3_stmt* s, int col) {
  if (sqlite3_column_type(s, col) == SQLITE_NULL) return std::nullopt;
  return ColumnNumber(s, col);
}

std::vector<int> IntListFromText(const std::string& text) {
  std::vector<int> out;
  if (text.empty()) return out;
  const nlohmann::json j = nlohmann::json::parse(text);
  if (!j.is_array()) throw std::invalid_argument("not a list");
  for (const auto& v : j) {
    if (!v.is_number_integer() || v.get<int64_t>() < INT_MIN || v.get<int64_t>() > INT_MAX)
      throw std::invalid_argument("not an integer");
    out.push_back(v.get<int>());
  }
  return out;
}

// Throws on a row that cannot be a detection (Detections() skips it).
Detection ReadDetectionRow(sqlite3_stmt* s) {
  Detection d;
  d.id = sqlite3_column_int64(s, 0);
  d.class_name = ColumnText(s, 1);
  d.score = ColumnNumber(s, 2);
  d.position = {ColumnNumber(s, 3), ColumnNumber(s, 4)};
  if (std::abs(d.position.lat) > 90 || std::abs(d.position.lon) > 180) throw std::invalid_argument("off the globe");
  d.note = ColumnText(s, 5);
  d.source = ColumnText(s, 6);
  if (sqlite3_column_type(s, 7) != SQLITE_NULL) d.frame_id = sqlite3_column_int(s, 7);
  d.time_s = ColumnFiniteOptional(s, 8);
  d.created = ColumnText(s, 9);
  d.updated = ColumnText(s, 10);
  d.seq = sqlite3_column_int64(s, 11);
  d.model = ColumnText(s, 12);
  if (sqlite3_column_type(s, 13) != SQLITE_NULL) d.level = sqlite3_column_int(s, 13);
  d.levels = IntListFromText(ColumnText(s, 14));
  const std::string box = ColumnText(s, 15);
  if (!box.empty()) {
    const nlohmann::json j = nlohmann::json::parse(box);
    if (!j.is_null() && !j.is_array()) throw std::invalid_argument("box: not a list");
    if (j.is_array())
      for (const auto& c : j)
        if (!c.is_array() || c.size() < 2 || !c[0].is_number() || !c[1].is_number() ||
            !std::isfinite(c[0].get<double>()) || !std::isfinite(c[1].get<double>()))
          throw std::invalid_argument("box: not [lon, lat] pairs");
    d.box = BoxFromJson(j);
  }
  if (ColumnsSet(s, 16, 17)) d.position_m = std::array<double, 2>{ColumnNumber(s, 16), ColumnNumber(s, 17)};
  if (ColumnsSet(s, 18, 19)) d.size_m = std::array<double, 2>{ColumnNumber(s, 18), ColumnNumber(s, 19)};
  d.frames = IntListFromText(ColumnText(s, 20));
  d.status = ColumnText(s, 21);
  d.truncated = sqlite3_column_int(s, 22) != 0;
  d.alt_class = ColumnText(s, 23);
  d.heading_deg = ColumnFiniteOptional(s, 24);
  d.depth_m = ColumnFiniteOptional(s, 25);
  d.sigma_m = ColumnFiniteOptional(s, 26);
  NormaliseDetection(&d);
  return d;
}
}  // namespace

MBTilesStore::MBTilesStore(const std::string& path, Mode mode) : path_(path), mode_(mode) {
  const bool read_only = mode == Mode::kReadOnly;
  const std::string field = read_only ? "" : "--out";
  const std::string action = read_only ? "cannot open MBTiles file: " : "cannot create MBTiles file: ";
  if (read_only && !std::filesystem::is_regular_file(path)) throw InputError(path, 0, field, action + "no such file");
  const int flags = read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  int rc = sqlite3_open_v2(path.c_str(), &db_, flags | SQLITE_OPEN_NOMUTEX, nullptr);
  try {
    if (rc != SQLITE_OK) Fail("open");
    sqlite3_busy_timeout(db_, 5000);  // another process may hold the write lock briefly
    if (read_only) {
      OneShot check{Prepare("SELECT 1 FROM sqlite_master WHERE type='table' AND name='tiles'")};
      rc = sqlite3_step(check.s);
      if (rc == SQLITE_DONE) throw std::runtime_error("not an MBTiles file (no 'tiles' table)");
      if (rc != SQLITE_ROW) Fail("read");
    } else {
      Exec("PRAGMA page_size=16384");  // a tile (tens of KB) in two pages, not a chain of eight
      Exec("PRAGMA journal_mode=WAL");
      Exec("PRAGMA synchronous=NORMAL");
      Exec(kSchema);
      AddMissingColumns(db_, "frames", kFrameNavColumns);  // a mission written before they existed
      AddMissingColumns(db_, "track", kTrackNavColumns);
      AddMissingColumns(db_, "detections", kDetectionObjectColumns);
      // Before `model`, a recogniser's name was kept in `source`.
      Exec(
          "UPDATE detections SET model = source, source = 'recogniser' "
          "WHERE source NOT IN ('recogniser', 'operator', 'stereo') AND (model IS NULL OR model = '')");
      put_tile_ = Prepare(
          "INSERT OR REPLACE INTO tiles (zoom_level, tile_column, tile_row, tile_data) "
          "VALUES (?, ?, ?, ?)");
      put_meta_ = Prepare("INSERT OR REPLACE INTO metadata (name, value) VALUES (?, ?)");
      put_frame_ = Prepare(InsertSql("frames", kFrameColumns).c_str());
      put_track_ = Prepare(InsertSql("track", kTrackColumns).c_str());
    }
    get_tile_ = Prepare("SELECT tile_data FROM tiles WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?");
    journal_ = std::make_unique<MBTilesJournal>(db_);
    opened_ = true;
  } catch (const std::exception& e) {
    std::string message = e.what();
    for (sqlite3_stmt* s : {put_tile_, get_tile_, put_meta_, put_frame_, put_track_}) sqlite3_finalize(s);
    sqlite3_close(db_);
    db_ = nullptr;
    throw InputError(path, 0, field, action + message);
  }
}

MBTilesStore::~MBTilesStore() {
  try {
    Flush();
  } catch (...) {  // destructors must not throw; Flush() explicitly to see errors
  }
  journal_.reset();  // its statements first: SQLite closes no connection with statements open
  for (sqlite3_stmt* s : {put_tile_, get_tile_, put_meta_, put_frame_, put_track_}) sqlite3_finalize(s);
  sqlite3_close(db_);
}

void MBTilesStore::Fail(const std::string& what) const {
  // While opening, the constructor wraps this in an InputError naming the path.
  std::string message = what + ": " + (db_ ? sqlite3_errmsg(db_) : "out of memory");
  throw std::runtime_error(opened_ ? path_ + ": " + message : message);
}

sqlite3_stmt* MBTilesStore::Prepare(const char* sql) const {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db_, sql, -1, &s, nullptr) != SQLITE_OK) Fail("prepare");
  return s;
}

void MBTilesStore::Exec(const char* sql) const {
  if (sqlite3_exec(db_, sql, nullptr, nullptr, nullptr) != SQLITE_OK) Fail(sql);
}

void MBTilesStore::BeginWrite() {
  if (mode_ == Mode::kReadOnly) throw std::runtime_error(path_ + ": opened read-only");
  // SQLite may have rolled a failed transaction back by itself: ask it.
  if (!in_transaction_ || sqlite3_get_autocommit(db_)) {
    Exec("BEGIN IMMEDIATE");
    in_transaction_ = true;
    pending_writes_ = 0;
  }
}

void MBTilesStore::EndWrite() {
  if (++pending_writes_ >= kMaxPendingWrites) CommitLocked();
}

void MBTilesStore::CommitLocked() {
  if (!in_transaction_) return;
  if (sqlite3_get_autocommit(db_)) {  // already rolled back by SQLite after an error
    in_transaction_ = false;
    pending_writes_ = 0;
    return;
  }
  Exec("COMMIT");
  in_transaction_ = false;
  pending_writes_ = 0;
}

void MBTilesStore::AbandonLocked() {
  if (in_transaction_ && !sqlite3_get_autocommit(db_)) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  in_transaction_ = false;
  pending_writes_ = 0;
}

void MBTilesStore::Flush() {
  std::lock_guard<std::mutex> lock(mutex_);
  CommitLocked();
}

void MBTilesStore::PutTile(const TileId& id, const std::vector<uint8_t>& bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  PutTileLocked("", put_tile_, id, bytes);
}

void MBTilesStore::PutTileLocked(const std::string& layer, sqlite3_stmt* put, const TileId& id,
                                 const std::vector<uint8_t>& bytes) {
  BeginWrite();
  journal_->BeforeTileWrite(layer, id);
  StatementReset reset(put);
  sqlite3_bind_int(put, 1, id.z);
  sqlite3_bind_int(put, 2, id.x);
  sqlite3_bind_int(put, 3, id.TmsRow());
  sqlite3_bind_blob(put, 4, bytes.data(), static_cast<int>(bytes.size()), SQLITE_STATIC);
  if (sqlite3_step(put) != SQLITE_DONE) Fail("write tile");
  EndWrite();
}

std::optional<std::vector<uint8_t>> MBTilesStore::GetTile(const TileId& id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return GetTileLocked(get_tile_, id);
}

std::optional<std::vector<uint8_t>> MBTilesStore::GetTileLocked(sqlite3_stmt* get, const TileId& id) const {
  StatementReset reset(get);
  sqlite3_bind_int(get, 1, id.z);
  sqlite3_bind_int(get, 2, id.x);
  sqlite3_bind_int(get, 3, id.TmsRow());
  const int rc = sqlite3_step(get);
  if (rc == SQLITE_DONE) return std::nullopt;
  if (rc != SQLITE_ROW) Fail("read tile");
  const auto* data = static_cast<const uint8_t*>(sqlite3_column_blob(get, 0));
  return std::vector<uint8_t>(data, data + sqlite3_column_bytes(get, 0));
}

int64_t MBTilesStore::TileCount() const {
  return CountRows("tiles");
}

std::vector<TileId> MBTilesStore::TileIds() const {
  return ReadTileIds("tiles");
}

std::vector<TileId> MBTilesStore::ReadTileIds(const std::string& table) const {
  std::lock_guard<std::mutex> lock(mutex_);
  OneShot q{Prepare(("SELECT zoom_level, tile_column, tile_row FROM " + table).c_str())};
  std::vector<TileId> out;
  int rc;
  while ((rc = sqlite3_step(q.s)) == SQLITE_ROW) {
    const int z = sqlite3_column_int(q.s, 0);
    out.push_back(TileId{z, sqlite3_column_int(q.s, 1), (1 << z) - 1 - sqlite3_column_int(q.s, 2)});
  }
  if (rc != SQLITE_DONE) Fail("list tiles");
  return out;
}

int64_t MBTilesStore::CountRows(const std::string& table) const {
  std::lock_guard<std::mutex> lock(mutex_);
  OneShot q{Prepare(("SELECT COUNT(*) FROM " + table).c_str())};
  if (sqlite3_step(q.s) != SQLITE_ROW) Fail("count tiles");
  return sqlite3_column_int64(q.s, 0);
}

void MBTilesStore::WriteCheckpointOf(const std::string& layer, const CheckpointUpdate& update) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  try {
    journal_->Write(layer, update);
  } catch (...) {
    AbandonLocked();  // half a checkpoint must never be committed
    throw;
  }
  CommitLocked();
}

std::optional<StoredCheckpoint> MBTilesStore::ReadCheckpoint() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return journal_->Read("");
}

std::optional<std::vector<uint8_t>> MBTilesStore::ReadCheckpointBlob(int kind, const TileId& id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return journal_->ReadBlob("", kind, id);
}

void MBTilesStore::RollBackOf(const std::string& layer) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  try {
    journal_->RollBack(layer);
  } catch (...) {
    AbandonLocked();
    throw;
  }
  CommitLocked();
}

bool MBTilesStore::RollBackToStartOf(const std::string& layer) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  bool kept = false;
  try {
    kept = journal_->RollBackToStart(layer);
  } catch (...) {
    AbandonLocked();
    throw;
  }
  CommitLocked();
  return kept;
}

void MBTilesStore::DropOf(const std::string& layer) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  journal_->Drop(layer);
}

void MBTilesStore::SetMetadata(const std::string& key, const std::string& value) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  StatementReset reset(put_meta_);
  sqlite3_bind_text(put_meta_, 1, key.c_str(), -1, SQLITE_STATIC);
  sqlite3_bind_text(put_meta_, 2, value.c_str(), -1, SQLITE_STATIC);
  if (sqlite3_step(put_meta_) != SQLITE_DONE) Fail("write metadata");
  EndWrite();
}

std::map<std::string, std::string> MBTilesStore::Metadata() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<std::string, std::string> out;
  OneShot q{Prepare("SELECT name, value FROM metadata")};
  int rc;
  while ((rc = sqlite3_step(q.s)) == SQLITE_ROW) out[ColumnText(q.s, 0)] = ColumnText(q.s, 1);
  if (rc != SQLITE_DONE) Fail("read metadata");
  return out;
}

void MBTilesStore::PutFrame(const FrameRecord& f) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  StatementReset reset(put_frame_);
  const std::string footprint = FootprintToJson(f.footprint).dump();
  sqlite3_stmt* s = put_frame_;
  sqlite3_bind_int(s, 1, f.id);
  sqlite3_bind_text(s, 2, f.image.c_str(), -1, SQLITE_STATIC);
  sqlite3_bind_text(s, 3, f.image_path.c_str(), -1, SQLITE_STATIC);
  BindOptional(s, 4, f.time_s);
  sqlite3_bind_double(s, 5, f.position.lat);
  sqlite3_bind_double(s, 6, f.position.lon);
  sqlite3_bind_double(s, 7, f.altitude_m);
  sqlite3_bind_double(s, 8, f.depth_m);
  sqlite3_bind_double(s, 9, f.heading_deg);
  sqlite3_bind_double(s, 10, f.pitch_deg);
  sqlite3_bind_double(s, 11, f.roll_deg);
  sqlite3_bind_text(s, 12, footprint.c_str(), -1, SQLITE_STATIC);
  sqlite3_bind_text(s, 13, f.status.c_str(), -1, SQLITE_STATIC);
  if (f.nav) {  // unbound parameters are NULL
    const NavigatedPose& n = *f.nav;
    int col = 14;
    for (double v : {n.position.lat, n.position.lon, n.altitude_m, n.depth_m, n.heading_deg, n.pitch_deg, n.roll_deg})
      sqlite3_bind_double(s, col++, v);
  }
  if (sqlite3_step(s) != SQLITE_DONE) Fail("write frame");
  EndWrite();
}

void MBTilesStore::PutTrackPoint(const TrackPoint& p) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  StatementReset reset(put_track_);
  sqlite3_stmt* s = put_track_;
  sqlite3_bind_int(s, 1, p.seq);
  BindOptional(s, 2, p.time_s);
  sqlite3_bind_double(s, 3, p.position.lat);
  sqlite3_bind_double(s, 4, p.position.lon);
  sqlite3_bind_double(s, 5, p.altitude_m);
  sqlite3_bind_double(s, 6, p.depth_m);
  sqlite3_bind_double(s, 7, p.heading_deg);
  if (p.nav) {
    sqlite3_bind_double(s, 8, p.nav->position.lat);
    sqlite3_bind_double(s, 9, p.nav->position.lon);
    sqlite3_bind_double(s, 10, p.nav->heading_deg);
  }
  if (sqlite3_step(s) != SQLITE_DONE) Fail("write track point");
  EndWrite();
}

template <typename Row>
std::vector<Row> MBTilesStore::ReadRows(const std::string& table, const std::vector<std::string>& columns,
                                        const char* order, const char* what, Row (*read_row)(sqlite3_stmt*)) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Row> out;
  // Asked each time: a writer in another process may add columns meanwhile.
  const std::string sql =
      "SELECT " + SelectList(TableColumns(db_, table), columns) + " FROM " + table + " ORDER BY " + order;
  sqlite3_stmt* s = nullptr;
  // A plain MBTiles file from another tool lacks our mission tables: no rows.
  if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &s, nullptr) != SQLITE_OK) {
    sqlite3_finalize(s);
    return out;
  }
  OneShot q{s};
  sqlite3_stmt* count = nullptr;  // the rows, to allocate once (a long list grows no second copy)
  if (sqlite3_prepare_v2(db_, ("SELECT COUNT(*) FROM " + table).c_str(), -1, &count, nullptr) == SQLITE_OK &&
      sqlite3_step(count) == SQLITE_ROW)
    out.reserve(static_cast<size_t>(std::max<int64_t>(0, sqlite3_column_int64(count, 0))));
  sqlite3_finalize(count);
  int rc;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) out.push_back(read_row(s));
  if (rc != SQLITE_DONE) Fail(what);
  return out;
}

std::vector<FrameRecord> MBTilesStore::Frames() const {
  return ReadRows<FrameRecord>("frames", kFrameColumns, "id", "read frames", [](sqlite3_stmt* s) {
    FrameRecord f;
    f.id = sqlite3_column_int(s, 0);
    f.image = ColumnText(s, 1);
    f.image_path = ColumnText(s, 2);
    f.time_s = ColumnOptional(s, 3);
    f.position = {sqlite3_column_double(s, 4), sqlite3_column_double(s, 5)};
    f.altitude_m = sqlite3_column_double(s, 6);
    f.depth_m = sqlite3_column_double(s, 7);
    f.heading_deg = sqlite3_column_double(s, 8);
    f.pitch_deg = sqlite3_column_double(s, 9);
    f.roll_deg = sqlite3_column_double(s, 10);
    const std::string footprint = ColumnText(s, 11);
    if (!footprint.empty()) f.footprint = FootprintFromJson(nlohmann::json::parse(footprint));
    f.status = ColumnText(s, 12);
    if (ColumnsSet(s, 13, 14)) {
      NavigatedPose& n = f.nav.emplace();
      n.position = {sqlite3_column_double(s, 13), sqlite3_column_double(s, 14)};
      n.altitude_m = sqlite3_column_double(s, 15);
      n.depth_m = sqlite3_column_double(s, 16);
      n.heading_deg = sqlite3_column_double(s, 17);
      n.pitch_deg = sqlite3_column_double(s, 18);
      n.roll_deg = sqlite3_column_double(s, 19);
    }
    return f;
  });
}

std::vector<TrackPoint> MBTilesStore::Track() const {
  return ReadRows<TrackPoint>("track", kTrackColumns, "seq", "read track", [](sqlite3_stmt* s) {
    TrackPoint p;
    p.seq = sqlite3_column_int(s, 0);
    p.time_s = ColumnOptional(s, 1);
    p.position = {sqlite3_column_double(s, 2), sqlite3_column_double(s, 3)};
    p.altitude_m = sqlite3_column_double(s, 4);
    p.depth_m = sqlite3_column_double(s, 5);
    p.heading_deg = sqlite3_column_double(s, 6);
    if (ColumnsSet(s, 7, 8))
      p.nav =
          NavigatedPosition{{sqlite3_column_double(s, 7), sqlite3_column_double(s, 8)}, sqlite3_column_double(s, 9)};
    return p;
  });
}

void MBTilesStore::PutDetection(const Detection& d) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  OneShot q{Prepare(InsertSql("detections", kDetectionColumns).c_str())};
  sqlite3_stmt* s = q.s;
  // Bound texts must outlive the step: SQLITE_TRANSIENT copies them.
  auto text = [s](int col, const std::string& v) { sqlite3_bind_text(s, col, v.c_str(), -1, SQLITE_TRANSIENT); };
  auto optional_int = [s](int col, const std::optional<int>& v) {
    if (v)
      sqlite3_bind_int(s, col, *v);
    else
      sqlite3_bind_null(s, col);
  };
  sqlite3_bind_int64(s, 1, d.id);
  text(2, d.class_name);
  sqlite3_bind_double(s, 3, d.score);
  sqlite3_bind_double(s, 4, d.position.lat);
  sqlite3_bind_double(s, 5, d.position.lon);
  text(6, d.note);
  text(7, d.source);
  optional_int(8, d.frame_id);
  BindOptional(s, 9, d.time_s);
  text(10, d.created);
  text(11, d.updated);
  sqlite3_bind_int64(s, 12, d.seq);
  text(13, d.model);
  optional_int(14, d.level);
  text(15, nlohmann::json(d.levels).dump());
  text(16, d.box.empty() ? "" : BoxToJson(d.box).dump());
  BindOptional(s, 17, d.position_m ? std::optional<double>((*d.position_m)[0]) : std::nullopt);
  BindOptional(s, 18, d.position_m ? std::optional<double>((*d.position_m)[1]) : std::nullopt);
  BindOptional(s, 19, d.size_m ? std::optional<double>((*d.size_m)[0]) : std::nullopt);
  BindOptional(s, 20, d.size_m ? std::optional<double>((*d.size_m)[1]) : std::nullopt);
  text(21, nlohmann::json(d.frames).dump());
  text(22, d.status);
  sqlite3_bind_int(s, 23, d.truncated ? 1 : 0);
  text(24, d.alt_class);
  BindOptional(s, 25, d.heading_deg);
  BindOptional(s, 26, d.depth_m);
  BindOptional(s, 27, d.sigma_m);
  if (sqlite3_step(s) != SQLITE_DONE) Fail("write detection");
  EndWrite();
}

void MBTilesStore::PutTerrain(const TerrainBlob& terrain) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  // Made here, not with the schema: a map without a height model stays as it was.
  Exec("CREATE TABLE IF NOT EXISTS terrain (id integer primary key, header text, cells blob)");
  OneShot q{Prepare("INSERT OR REPLACE INTO terrain (id, header, cells) VALUES (0, ?, ?)")};
  sqlite3_bind_text(q.s, 1, terrain.header_json.c_str(), -1, SQLITE_STATIC);
  sqlite3_bind_blob64(q.s, 2, terrain.cells.data(), terrain.cells.size(), SQLITE_STATIC);
  if (sqlite3_step(q.s) != SQLITE_DONE) Fail("write terrain");
  EndWrite();
}

std::optional<TerrainBlob> MBTilesStore::Terrain() const {
  std::lock_guard<std::mutex> lock(mutex_);
  {
    OneShot exists{Prepare("SELECT 1 FROM sqlite_master WHERE type='table' AND name='terrain'")};
    const int rc = sqlite3_step(exists.s);
    if (rc == SQLITE_DONE) return std::nullopt;
    if (rc != SQLITE_ROW) Fail("read terrain");
  }
  OneShot q{Prepare("SELECT header, cells FROM terrain WHERE id = 0")};
  const int rc = sqlite3_step(q.s);
  if (rc == SQLITE_DONE) return std::nullopt;
  if (rc != SQLITE_ROW) Fail("read terrain");
  TerrainBlob out;
  out.header_json = ColumnText(q.s, 0);
  const auto* cells = static_cast<const uint8_t*>(sqlite3_column_blob(q.s, 1));
  out.cells.assign(cells, cells + sqlite3_column_bytes(q.s, 1));
  return out;
}

void MBTilesStore::DeleteDetection(int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  BeginWrite();
  OneShot q{Prepare("DELETE FROM detections WHERE id = ?")};
  sqlite3_bind_int64(q.s, 1, id);
  if (sqlite3_step(q.s) != SQLITE_DONE) Fail("delete detection");
  EndWrite();
}

std::vector<Detection> MBTilesStore::Detections() const {
  // A row that cannot be a detection (a number NULL, not finite or off the
  // globe, a JSON column that does not parse: a search that stored inf/NaN, a
  // hand edit) is skipped and counted, so one bad row never makes the map
  // unreadable for serve, export and detections-pack. Read into one vector and
  // compacted in place: a mission of 232,362 detections holds one copy.
  std::vector<Detection> out =
      ReadRows<Detection>("detections", kDetectionColumns, "id", "read detections", [](sqlite3_stmt* s) {
        try {
          return ReadDetectionRow(s);
        } catch (const std::exception&) {
          Detection unreadable;  // marked by both numbers at their least, which no store writes
          unreadable.id = unreadable.seq = std::numeric_limits<int64_t>::min();
          return unreadable;
        }
      });
  const size_t read = out.size();
  out.erase(std::remove_if(out.begin(), out.end(),
                           [](const Detection& d) {
                             return d.id == std::numeric_limits<int64_t>::min() &&
                                    d.seq == std::numeric_limits<int64_t>::min();
                           }),
            out.end());
  skipped_detections_ = static_cast<int64_t>(read - out.size());
  return out;
}

std::vector<Detection> MBTilesStore::ReadableDetections(std::vector<int64_t>* unreadable) const {
  using Row = std::pair<int64_t, std::optional<Detection>>;
  const auto rows = ReadRows<Row>("detections", kDetectionColumns, "id", "read detections", [](sqlite3_stmt* s) {
    const int64_t id = sqlite3_column_int64(s, 0);
    // SQLite keeps a NaN as NULL, which reads back as 0: a missing position is no position.
    if (sqlite3_column_type(s, 3) == SQLITE_NULL || sqlite3_column_type(s, 4) == SQLITE_NULL) return Row{id, {}};
    try {
      Detection d = ReadDetectionRow(s);
      return IsFiniteDetection(d) ? Row{id, std::move(d)} : Row{id, {}};
    } catch (const std::exception&) {  // a box or list with nulls
      return Row{id, {}};
    }
  });
  std::vector<Detection> out;
  for (const auto& [id, d] : rows) {
    if (d)
      out.push_back(*d);
    else if (unreadable)
      unreadable->push_back(id);
  }
  return out;
}

}  // namespace seamap
