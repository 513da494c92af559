#pragma once
// A folder pyramid {root}/{z}/{x}/{y}.{ext} (XYZ rows) as any static web
// server can serve it, with TileJSON 3.0.0 `metadata.json`, and the mission
// records in `frames.json`, `track.json` and `detections.json`, the height
// model in `terrain.json` + `terrain.bin`. Every file is written atomically
// (temp file in the same folder, then rename), so a reader never sees half a
// tile. Tiles are written at once; the JSON files on Flush().
#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>

#include <nlohmann/json.hpp>

#include "core/tiles/tile_store.h"

namespace seamap {

// Keeps the mission's records itself; no build checkpoints (writing a tile
// is a rename, there is no transaction to journal in).
class FolderStore : public TileStore, public MissionRecords {
 public:
  enum class Mode {
    kCreate,    // create the folder if missing, or open it to continue writing
    kReadOnly,  // the folder must exist; Put*/SetMetadata throw
  };

  // `extension`: tile file extension ("png", "jpg", "webp"). An existing
  // folder's metadata.json, frames.json and track.json are loaded.
  // Throws InputError(root, 0, "--out", "cannot create tile folder: ...") in
  // kCreate mode, InputError(root, 0, "", "cannot open tile folder: ...") in kReadOnly.
  FolderStore(const std::string& root, const std::string& extension, Mode mode = Mode::kCreate);
  ~FolderStore() override;  // flushes pending JSON files
  FolderStore(const FolderStore&) = delete;
  FolderStore& operator=(const FolderStore&) = delete;

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
  int64_t SkippedDetections() const override;
  // terrain.bin (the cells) then terrain.json (the header), each written atomically
  // at once; the header's size and checksum tell a reader a pair that does not match.
  void PutTerrain(const TerrainBlob& terrain) override;
  std::optional<TerrainBlob> Terrain() const override;

  void Flush() override;
  // Layers live in root/layers/<name>/ as folder pyramids of their own.
  std::unique_ptr<TileStore> OpenLayer(const std::string& name) override;

  std::filesystem::path TilePath(const TileId& id) const;  // root/z/x/y.ext
  const std::filesystem::path& root() const { return root_; }

 protected:
  MissionRecords& RecordsKept() override { return *this; }

 private:
  CheckpointStore* CheckpointsKept() override { return nullptr; }
  void Load();
  void CheckWritable() const;
  void WriteJsonLocked();

  std::filesystem::path root_;
  std::string extension_;
  Mode mode_;
  mutable std::mutex mutex_;
  std::atomic<int64_t> tile_count_{0};
  bool dirty_ = false;
  std::map<std::string, std::string> metadata_;
  std::map<int, FrameRecord> frames_;                  // by id: Put replaces
  std::map<int, TrackPoint> track_;                    // by seq
  std::map<int64_t, Detection> detections_;            // by id
  std::vector<nlohmann::json> unreadable_detections_;  // records that are no detection, kept verbatim
};

// TileJSON 3.0.0 document for MBTiles-style string metadata: "bounds",
// "center", "minzoom", "maxzoom" become numbers, other keys stay strings.
nlohmann::json MetadataToTileJson(const std::map<std::string, std::string>& metadata, const std::string& extension);
// The inverse (numbers back to MBTiles strings "w,s,e,n", "lon,lat,z").
std::map<std::string, std::string> MetadataFromTileJson(const nlohmann::json& tilejson);

}  // namespace seamap
