#pragma once
// Where encoded tiles and the mission's records live. Implementations are
// safe to call from several threads (one writer thread plus readers).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/geo/web_mercator.h"
#include "core/tiles/mission_records.h"
#include "core/tiles/store_checkpoint.h"

namespace seamap {

// Tiles, their metadata and the store's layers. The mission's records and
// the build checkpoints are kept in the same file or folder but are
// interfaces of their own (Records, Checkpoints).
class TileStore {
 public:
  virtual ~TileStore() = default;

  // Tiles. Put replaces any previous tile at the same id.
  virtual void PutTile(const TileId& id, const std::vector<uint8_t>& bytes) = 0;
  virtual std::optional<std::vector<uint8_t>> GetTile(const TileId& id) const = 0;
  virtual int64_t TileCount() const = 0;
  // Every tile id the store holds (for exports), in no particular order.
  virtual std::vector<TileId> TileIds() const = 0;

  // Metadata (MBTiles metadata table / TileJSON keys). Values are strings as
  // MBTiles 1.3 stores them ("bounds" = "w,s,e,n", "center" = "lon,lat,z").
  virtual void SetMetadata(const std::string& key, const std::string& value) = 0;
  virtual std::map<std::string, std::string> Metadata() const = 0;

  // Makes everything written so far durable and visible to other readers
  // (commits the open transaction / writes metadata files): tiles, metadata,
  // records and checkpoints alike.
  virtual void Flush() = 0;

  // A named extra tile layer of the same mission (e.g. "enhanced"): its own
  // tiles, metadata and checkpoint, the mission's records (LayerRecords). The
  // returned store must not outlive this one. Names are [a-z0-9_]+ (InputError otherwise).
  virtual std::unique_ptr<TileStore> OpenLayer(const std::string& name) = 0;

  // The mission's frames, track and detections (core/tiles/mission_records.h).
  MissionRecords& Records() { return RecordsKept(); }
  const MissionRecords& Records() const { return const_cast<TileStore*>(this)->RecordsKept(); }

  // The build checkpoints (core/tiles/store_checkpoint.h); null where the
  // store keeps none (a tile folder).
  CheckpointStore* Checkpoints() { return CheckpointsKept(); }
  const CheckpointStore* Checkpoints() const { return const_cast<TileStore*>(this)->CheckpointsKept(); }

 private:
  // What Records and Checkpoints return (one override each, for both constnesses).
  virtual MissionRecords& RecordsKept() = 0;
  virtual CheckpointStore* CheckpointsKept() = 0;
};

// The store's checkpoint; none where it keeps none.
std::optional<StoredCheckpoint> ReadStoredCheckpoint(const TileStore& store);

// Throws InputError(name, 0, "layer", ...) unless name matches [a-z0-9_]{1,32}.
void CheckLayerName(const std::string& name);

// A path ending in ".mbtiles" names an MBTiles file; anything else a folder pyramid.
bool IsMBTilesPath(const std::string& path);

// Opens a map that exists, read-only or to write (operator marks, more tiles):
// an MBTiles file, or a folder pyramid whose tile extension comes from its
// metadata.json. Throws InputError naming the path when it is not a map.
std::unique_ptr<TileStore> OpenExistingMap(const std::string& path, bool writable);

// Deletes a map so it can be replaced: an MBTiles file with its -wal/-shm
// files, or a folder pyramid (one with metadata.json). A non-empty folder that
// is not a pyramid is refused: InputError(path, 0, param, ...).
void RemoveMap(const std::string& path, const std::string& param);

// Opens or creates a store: a path ending in ".mbtiles" is an MBTiles file,
// anything else a folder pyramid {z}/{x}/{y}.{ext} with metadata.json.
// `extension` is the tile file extension used by folder stores ("png"...).
// Throws InputError naming the path when it cannot be created or written.
std::unique_ptr<TileStore> OpenTileStore(const std::string& path, const std::string& extension, bool create);

}  // namespace seamap
