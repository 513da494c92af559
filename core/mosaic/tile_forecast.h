#pragma once
// Offline builds know every pose before the first frame. The forecast lists,
// for each base tile, the frames whose box will be over it, so the tile
// buffer can keep a tile that the next survey line comes back to instead of
// writing it and reading it back (on the bench survey every tile is then
// written once). Live builds have no forecast.
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/geo/web_mercator.h"

namespace seamap {

// Base tiles [x0, x1] x [y0, y1] under a box of global pixels. Rows are
// clipped to the tiles that exist at the zoom (past the Mercator limits
// nothing is mapped). Columns are not: a box may run past the antimeridian
// (seabed_projection.h), and column x stands for tile WrapTileX(zoom, x), at
// most the world's width of them. Empty when x0 > x1 or y0 > y1.
struct TileRange {
  int64_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};
TileRange TilesUnder(int zoom, int tile_size, int64_t x0, int64_t y0, int64_t width, int64_t height);
// The tile column that column x (of a TileRange) is, in [0, 2^zoom).
int WrapTileX(int zoom, int64_t x);

class TileForecast {
 public:
  // Frame `index` (acquisition order) will be over `tiles` at `zoom`.
  void Add(int index, int zoom, const TileRange& tiles);
  // Whether a frame with an index in (after, after + horizon] will be over the tile.
  bool OverSoon(const TileId& id, int after, int horizon) const;
  bool empty() const { return frames_over_.empty(); }

 private:
  std::unordered_map<TileId, std::vector<int>, TileIdHash> frames_over_;  // indices, ascending
};

}  // namespace seamap
