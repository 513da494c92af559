#include "core/tiles/tile_store.h"

#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"

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

}  // namespace seamap
