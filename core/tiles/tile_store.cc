#include "core/tiles/tile_store.h"

#include <algorithm>

#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"
#include "core/util/error.h"

namespace seamap {

std::unique_ptr<TileStore> OpenTileStore(const std::string& path, const std::string& extension,
                                         bool create) {
  const std::string suffix = ".mbtiles";
  const bool mbtiles = path.size() >= suffix.size() &&
                       path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
  if (mbtiles)
    return std::make_unique<MBTilesStore>(
        path, create ? MBTilesStore::Mode::kCreate : MBTilesStore::Mode::kReadOnly);
  return std::make_unique<FolderStore>(
      path, extension, create ? FolderStore::Mode::kCreate : FolderStore::Mode::kReadOnly);
}

void CheckLayerName(const std::string& name) {
  const bool ok = !name.empty() && name.size() <= 32 &&
                  std::all_of(name.begin(), name.end(), [](char c) {
                    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
                  });
  if (!ok) throw InputError(name, 0, "layer", "layer names are 1-32 characters of a-z, 0-9 and _");
}

}  // namespace seamap
