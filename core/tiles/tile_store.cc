#include "core/tiles/tile_store.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"
#include "core/util/error.h"

namespace seamap {

std::optional<StoredCheckpoint> ReadStoredCheckpoint(const TileStore& store) {
  const CheckpointStore* checkpoints = store.Checkpoints();
  return checkpoints ? checkpoints->ReadCheckpoint() : std::nullopt;
}

bool IsMBTilesPath(const std::string& path) {
  const std::string suffix = ".mbtiles";
  return path.size() >= suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::unique_ptr<TileStore> OpenExistingMap(const std::string& path, bool writable) {
  if (IsMBTilesPath(path)) {
    if (!std::filesystem::is_regular_file(path))
      throw InputError(path, 0, "", "cannot open MBTiles file: no such file");
    return OpenTileStore(path, "png", writable);
  }
  // A folder's tile extension is in its TileJSON; a missing or unreadable one is the reader's to report.
  std::string extension = "png";
  std::ifstream probe(std::filesystem::path(path) / "metadata.json");
  if (probe) {
    try {
      extension = nlohmann::json::parse(probe).value("format", "png");
    } catch (const nlohmann::json::exception&) {
    }
  }
  if (writable && !std::filesystem::is_regular_file(std::filesystem::path(path) / "metadata.json"))
    throw InputError(path, 0, "", "is not a tile folder (no metadata.json); build one with seamap build");
  return OpenTileStore(path, extension, writable);
}

void RemoveMap(const std::string& path, const std::string& param) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (IsMBTilesPath(path)) {
    for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(path + suffix, ec);
  } else if (fs::exists(fs::path(path) / "metadata.json")) {
    fs::remove_all(path, ec);
  } else if (fs::exists(path, ec) && !fs::is_empty(path, ec)) {
    throw InputError(path, 0, param, "is a non-empty folder that is not a tile pyramid; refusing to delete it");
  }
}

std::unique_ptr<TileStore> OpenTileStore(const std::string& path, const std::string& extension, bool create) {
  if (IsMBTilesPath(path))
    return std::make_unique<MBTilesStore>(path, create ? MBTilesStore::Mode::kCreate : MBTilesStore::Mode::kReadOnly);
  return std::make_unique<FolderStore>(path, extension,
                                       create ? FolderStore::Mode::kCreate : FolderStore::Mode::kReadOnly);
}

void CheckLayerName(const std::string& name) {
  const bool ok = !name.empty() && name.size() <= 32 && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
  if (!ok) throw InputError(name, 0, "layer", "layer names are 1-32 characters of a-z, 0-9 and _");
}

}  // namespace seamap
