// MBTilesStore's named layers (MBTilesStore::OpenLayer).
#include <sqlite3.h>

#include <stdexcept>

#include "core/tiles/layer_records.h"
#include "core/tiles/mbtiles_store.h"

namespace seamap {

// A named extra tile layer in the same file: table tiles_<name> with the
// MBTiles tiles schema, metadata under "layer.<name>.<key>", its own
// checkpoint; the mission's records (LayerRecords).
class MBTilesStore::Layer : public TileStore, public CheckpointStore {
 public:
  Layer(MBTilesStore* parent, std::string name) : parent_(parent), name_(std::move(name)), records_(parent) {
    std::lock_guard<std::mutex> lock(parent_->mutex_);
    const std::string table = "tiles_" + name_;
    if (parent_->mode_ != Mode::kReadOnly) {
      parent_->Exec(("CREATE TABLE IF NOT EXISTS " + table +
                     " (zoom_level integer, tile_column integer, tile_row integer, tile_data blob);"
                     "CREATE UNIQUE INDEX IF NOT EXISTS " +
                     table + "_index ON " + table + " (zoom_level, tile_column, tile_row);")
                        .c_str());
      put_ = parent_->Prepare(
          ("INSERT OR REPLACE INTO " + table + " (zoom_level, tile_column, tile_row, tile_data) VALUES (?, ?, ?, ?)")
              .c_str());
    }
    get_ = parent_->Prepare(
        ("SELECT tile_data FROM " + table + " WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?").c_str());
  }
  ~Layer() override {
    sqlite3_finalize(put_);
    sqlite3_finalize(get_);
  }
  void PutTile(const TileId& id, const std::vector<uint8_t>& bytes) override {
    if (!put_) throw std::runtime_error(parent_->path_ + ": opened read-only");
    std::lock_guard<std::mutex> lock(parent_->mutex_);
    parent_->PutTileLocked(name_, put_, id, bytes);
  }
  std::optional<std::vector<uint8_t>> GetTile(const TileId& id) const override {
    std::lock_guard<std::mutex> lock(parent_->mutex_);
    return parent_->GetTileLocked(get_, id);
  }
  int64_t TileCount() const override { return parent_->CountRows("tiles_" + name_); }
  std::vector<TileId> TileIds() const override { return parent_->ReadTileIds("tiles_" + name_); }
  void SetMetadata(const std::string& key, const std::string& value) override {
    parent_->SetMetadata(Prefix() + key, value);
  }
  std::map<std::string, std::string> Metadata() const override {
    std::map<std::string, std::string> out;
    for (const auto& [k, v] : parent_->Metadata())
      if (k.compare(0, Prefix().size(), Prefix()) == 0) out[k.substr(Prefix().size())] = v;
    return out;
  }
  void Flush() override { parent_->Flush(); }
  std::unique_ptr<TileStore> OpenLayer(const std::string& name) override { return parent_->OpenLayer(name); }
  void WriteCheckpoint(const CheckpointUpdate& u) override { parent_->WriteCheckpointOf(name_, u); }
  std::optional<StoredCheckpoint> ReadCheckpoint() const override {
    std::lock_guard<std::mutex> lock(parent_->mutex_);
    return parent_->journal_->Read(name_);
  }
  std::optional<std::vector<uint8_t>> ReadCheckpointBlob(int kind, const TileId& id) const override {
    std::lock_guard<std::mutex> lock(parent_->mutex_);
    return parent_->journal_->ReadBlob(name_, kind, id);
  }
  void RollBackToCheckpoint() override { parent_->RollBackOf(name_); }
  bool RollBackToStart() override { return parent_->RollBackToStartOf(name_); }
  void DropCheckpoint() override { parent_->DropOf(name_); }

 private:
  MissionRecords& RecordsKept() override { return records_; }
  CheckpointStore* CheckpointsKept() override { return this; }
  std::string Prefix() const { return "layer." + name_ + "."; }
  MBTilesStore* parent_;
  std::string name_;
  LayerRecords records_;
  sqlite3_stmt* put_ = nullptr;
  sqlite3_stmt* get_ = nullptr;
};

std::unique_ptr<TileStore> MBTilesStore::OpenLayer(const std::string& name) {
  CheckLayerName(name);
  return std::make_unique<Layer>(this, name);
}

}  // namespace seamap
