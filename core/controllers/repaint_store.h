#pragma once
// A view of a map for painting some of its tiles again from scratch (live
// refinement, core/controllers/map_repaint.h): a MosaicBuilder given this
// store sees only the tiles it wrote itself (so it never blends new poses
// into the old pixels it replaces), writes only the base tiles in scope
// (and overviews when asked), and starts its frame and track records from
// id 0, so that a frame painted again replaces its own record.
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_set>

#include "core/tiles/tile_store.h"

namespace seamap {

using TileSet = std::unordered_set<TileId, TileIdHash>;

struct RepaintScope {
  int base_zoom = 0;
  std::optional<TileSet> base_tiles;  // the base tiles it may write; none: all of them
  bool overviews = true;              // write overview tiles (a whole map: yes)
  bool records = true;                // frames, track and metadata go to the map (a whole map: yes)
};

class RepaintStore : public TileStore {
 public:
  // `inner` must outlive this store.
  RepaintStore(TileStore* inner, RepaintScope scope);
  ~RepaintStore() override;

  void PutTile(const TileId& id, const std::vector<uint8_t>& bytes) override;
  // Only the tiles written through this store: what was there before is not read back.
  std::optional<std::vector<uint8_t>> GetTile(const TileId& id) const override;
  int64_t TileCount() const override;
  std::vector<TileId> TileIds() const override;
  void SetMetadata(const std::string& key, const std::string& value) override;
  std::map<std::string, std::string> Metadata() const override { return inner_->Metadata(); }
  void Flush() override { inner_->Flush(); }
  std::unique_ptr<TileStore> OpenLayer(const std::string& name) override;

  // The tiles written so far.
  TileSet Written() const;

 private:
  class Records;
  MissionRecords& RecordsKept() override;
  CheckpointStore* CheckpointsKept() override { return nullptr; }

  TileStore* inner_;
  RepaintScope scope_;
  std::unique_ptr<Records> records_;
  mutable std::mutex mutex_;
  TileSet written_;
};

}  // namespace seamap
