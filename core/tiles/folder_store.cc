#include "core/tiles/folder_store.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "core/tiles/layer_records.h"
#include "core/tiles/record_json.h"
#include "core/util/error.h"

namespace fs = std::filesystem;

namespace seamap {
namespace {

constexpr const char* kMetadataFile = "metadata.json";
constexpr const char* kFramesFile = "frames.json";
constexpr const char* kTrackFile = "track.json";
constexpr const char* kDetectionsFile = "detections.json";
constexpr const char* kTerrainHeaderFile = "terrain.json";
constexpr const char* kTerrainCellsFile = "terrain.bin";

// Writes through a temp file in the same folder and renames it over `path`,
// so readers see either the old or the new file, never a partial one.
void WriteFileAtomically(const fs::path& path, const char* data, size_t size) {
  static std::atomic<uint64_t> counter{0};
  fs::path tmp = path;
  tmp += ".tmp" + std::to_string(getpid()) + "_" + std::to_string(counter++);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(data, static_cast<std::streamsize>(size));
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error(path.string() + ": cannot write file");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot write file: " + ec.message());
  }
}

void WriteJsonFile(const fs::path& path, const nlohmann::json& j) {
  const std::string text = j.dump(1) + "\n";
  WriteFileAtomically(path, text.data(), text.size());
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

nlohmann::json ReadJsonFile(const fs::path& path) {
  try {
    return nlohmann::json::parse(ReadFile(path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string(), 0, "", std::string("invalid JSON: ") + e.what());
  }
}

// Shortest text that reads back as the same double ("3", "0.1", "-71.25").
std::string FormatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

// "a,b,c" -> numbers, or nothing when a part is not a number.
std::optional<std::vector<double>> ParseNumbers(const std::string& text, size_t count) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0') return std::nullopt;
    out.push_back(v);
  }
  if (out.size() != count) return std::nullopt;
  return out;
}

}  // namespace

nlohmann::json MetadataToTileJson(const std::map<std::string, std::string>& metadata, const std::string& extension) {
  nlohmann::json j = {{"tilejson", "3.0.0"}, {"tiles", {"{z}/{x}/{y}." + extension}}, {"scheme", "xyz"}};
  for (const auto& [key, value] : metadata) {
    std::optional<std::vector<double>> numbers;
    if (key == "bounds") numbers = ParseNumbers(value, 4);
    if (key == "center") numbers = ParseNumbers(value, 3);
    if (key == "minzoom" || key == "maxzoom") numbers = ParseNumbers(value, 1);
    if (!numbers) {
      j[key] = value;
    } else if (numbers->size() == 1) {
      j[key] = static_cast<int>((*numbers)[0]);
    } else {
      j[key] = *numbers;
    }
  }
  return j;
}

std::map<std::string, std::string> MetadataFromTileJson(const nlohmann::json& tilejson) {
  std::map<std::string, std::string> out;
  for (const auto& [key, value] : tilejson.items()) {
    if (key == "tilejson" || key == "tiles" || key == "scheme") continue;
    if (value.is_string()) {
      out[key] = value.get<std::string>();
    } else if (value.is_number()) {
      out[key] = FormatNumber(value.get<double>());
    } else if (value.is_array()) {
      std::string text;
      for (const auto& v : value)
        text += (text.empty() ? "" : ",") + (v.is_number() ? FormatNumber(v.get<double>()) : v.dump());
      out[key] = text;
    } else {
      out[key] = value.dump();
    }
  }
  return out;
}

FolderStore::FolderStore(const std::string& root, const std::string& extension, Mode mode)
    : root_(root), extension_(extension), mode_(mode) {
  if (mode == Mode::kReadOnly) {
    if (!fs::is_directory(root_)) throw InputError(root, 0, "", "cannot open tile folder: no such folder");
    Load();
    return;
  }
  try {
    fs::create_directories(root_);
    Load();
    // Writing the JSON files now reports an unwritable folder before any work.
    std::lock_guard<std::mutex> lock(mutex_);
    dirty_ = true;
    WriteJsonLocked();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(root, 0, "--out", std::string("cannot create tile folder: ") + e.what());
  }
}

FolderStore::~FolderStore() {
  try {
    Flush();
  } catch (...) {  // destructors must not throw; Flush() explicitly to see errors
  }
}

void FolderStore::Load() {
  if (fs::exists(root_ / kMetadataFile)) metadata_ = MetadataFromTileJson(ReadJsonFile(root_ / kMetadataFile));
  // Records are keyed by id / seq, so a later Put replaces an earlier one.
  const auto load = [this](const char* name, const auto& add) {
    const fs::path path = root_ / name;
    if (!fs::exists(path)) return;
    try {
      for (const auto& j : ReadJsonFile(path)) add(j);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(path.string(), 0, "", e.what());
    }
  };
  load(kFramesFile, [this](const nlohmann::json& j) {
    FrameRecord f = FrameFromJson(j);
    frames_[f.id] = f;
  });
  load(kTrackFile, [this](const nlohmann::json& j) {
    TrackPoint p = TrackPointFromJson(j);
    track_[p.seq] = p;
  });
  load(kDetectionsFile, [this](const nlohmann::json& j) {
    // A record that cannot be a detection (a search before issue 33 stored
    // inf/NaN as null) is kept as it was, written back, and counted: one bad
    // record never makes the map unreadable, and nothing is dropped.
    try {
      Detection d = DetectionFromJson(j);
      if (IsFiniteDetection(d)) {
        detections_[d.id] = d;
        return;
      }
    } catch (const nlohmann::json::exception&) {
    } catch (const std::invalid_argument&) {
    }
    unreadable_detections_.push_back(j);
  });
  // Tiles are the files two folders down: {z}/{x}/{y}.ext.
  int64_t count = 0;
  for (auto it = fs::recursive_directory_iterator(root_); it != fs::end(it); ++it)
    if (it.depth() == 2 && it->is_regular_file() && it->path().extension() == "." + extension_) ++count;
  tile_count_ = count;
}

void FolderStore::CheckWritable() const {
  if (mode_ == Mode::kReadOnly) throw std::runtime_error(root_.string() + ": opened read-only");
}

fs::path FolderStore::TilePath(const TileId& id) const {
  return root_ / std::to_string(id.z) / std::to_string(id.x) / (std::to_string(id.y) + "." + extension_);
}

void FolderStore::PutTile(const TileId& id, const std::vector<uint8_t>& bytes) {
  CheckWritable();
  const fs::path path = TilePath(id);
  fs::create_directories(path.parent_path());
  const bool is_new = !fs::exists(path);
  WriteFileAtomically(path, reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (is_new) ++tile_count_;
}

std::optional<std::vector<uint8_t>> FolderStore::GetTile(const TileId& id) const {
  std::ifstream in(TilePath(id), std::ios::binary);
  if (!in) return std::nullopt;
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

int64_t FolderStore::TileCount() const {
  return tile_count_;
}

std::vector<TileId> FolderStore::TileIds() const {
  std::vector<TileId> out;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(root_, ec); !ec && it != fs::end(it); it.increment(ec)) {
    if (it->path().filename() == "layers") {  // other layers' pyramids live below
      it.disable_recursion_pending();
      continue;
    }
    if (it.depth() != 2 || it->path().extension() != "." + extension_) continue;
    try {
      const fs::path& p = it->path();
      out.push_back(TileId{std::stoi(p.parent_path().parent_path().filename().string()),
                           std::stoi(p.parent_path().filename().string()), std::stoi(p.stem().string())});
    } catch (const std::exception&) {  // a stray file that is not {z}/{x}/{y}.ext
    }
  }
  return out;
}

void FolderStore::SetMetadata(const std::string& key, const std::string& value) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  metadata_[key] = value;
  dirty_ = true;
}

std::map<std::string, std::string> FolderStore::Metadata() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return metadata_;
}

void FolderStore::PutFrame(const FrameRecord& frame) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  frames_[frame.id] = frame;
  dirty_ = true;
}

void FolderStore::PutTrackPoint(const TrackPoint& point) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  track_[point.seq] = point;
  dirty_ = true;
}

std::vector<FrameRecord> FolderStore::Frames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<FrameRecord> out;
  for (const auto& [id, f] : frames_) out.push_back(f);
  return out;
}

std::vector<TrackPoint> FolderStore::Track() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<TrackPoint> out;
  for (const auto& [seq, p] : track_) out.push_back(p);
  return out;
}

void FolderStore::PutDetection(const Detection& detection) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  detections_[detection.id] = detection;
  dirty_ = true;
}

void FolderStore::DeleteDetection(int64_t id) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  detections_.erase(id);
  dirty_ = true;
}

std::vector<Detection> FolderStore::Detections() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Detection> out;
  for (const auto& [id, d] : detections_) out.push_back(d);
  return out;
}

std::vector<Detection> FolderStore::ReadableDetections(std::vector<int64_t>* unreadable) const {
  std::vector<Detection> out = MissionRecords::ReadableDetections(unreadable);
  std::lock_guard<std::mutex> lock(mutex_);
  if (unreadable)
    for (const auto& j : unreadable_detections_) {
      const auto id = j.is_object() ? j.find("id") : j.end();
      unreadable->push_back(id != j.end() && id->is_number_integer() ? id->get<int64_t>() : -1);
    }
  return out;
}

int64_t FolderStore::SkippedDetections() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int64_t>(unreadable_detections_.size());
}

void FolderStore::PutTerrain(const TerrainBlob& terrain) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  WriteFileAtomically(root_ / kTerrainCellsFile, reinterpret_cast<const char*>(terrain.cells.data()),
                      terrain.cells.size());
  WriteFileAtomically(root_ / kTerrainHeaderFile, terrain.header_json.data(), terrain.header_json.size());
}

std::optional<TerrainBlob> FolderStore::Terrain() const {
  std::lock_guard<std::mutex> lock(mutex_);
  const fs::path header = root_ / kTerrainHeaderFile, cells = root_ / kTerrainCellsFile;
  if (!fs::exists(header)) return std::nullopt;
  if (!fs::exists(cells))
    throw InputError(cells.string(), 0, "", "missing (terrain.json names the height model's cells)");
  TerrainBlob out;
  out.header_json = ReadFile(header);
  const std::string bytes = ReadFile(cells);
  out.cells.assign(bytes.begin(), bytes.end());
  return out;
}

void FolderStore::Flush() {
  std::lock_guard<std::mutex> lock(mutex_);
  WriteJsonLocked();
}

void FolderStore::WriteJsonLocked() {
  if (!dirty_ || mode_ == Mode::kReadOnly) return;
  WriteJsonFile(root_ / kMetadataFile, MetadataToTileJson(metadata_, extension_));
  nlohmann::json frames = nlohmann::json::array();
  for (const auto& [id, f] : frames_) frames.push_back(FrameToJson(f));
  WriteJsonFile(root_ / kFramesFile, frames);
  nlohmann::json track = nlohmann::json::array();
  for (const auto& [seq, p] : track_) track.push_back(TrackPointToJson(p));
  WriteJsonFile(root_ / kTrackFile, track);
  nlohmann::json detections = nlohmann::json::array();
  for (const auto& [id, d] : detections_) detections.push_back(DetectionToJson(d));
  for (const auto& j : unreadable_detections_) detections.push_back(j);
  WriteJsonFile(root_ / kDetectionsFile, detections);
  dirty_ = false;
}

namespace {
// A layer's tiles and metadata in root/layers/<name>/; the records are the
// mission's (LayerRecords), so the layer's own record files stay empty.
class FolderLayer : public FolderStore {
 public:
  FolderLayer(FolderStore* parent, const std::string& root, const std::string& ext, Mode mode)
      : FolderStore(root, ext, mode), records_(parent) {}

 private:
  MissionRecords& RecordsKept() override { return records_; }
  LayerRecords records_;
};
}  // namespace

std::unique_ptr<TileStore> FolderStore::OpenLayer(const std::string& name) {
  CheckLayerName(name);
  return std::make_unique<FolderLayer>(this, (root_ / "layers" / name).string(), extension_, mode_);
}

}  // namespace seamap
