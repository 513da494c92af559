#include "core/mosaic/tile_forecast.h"

#include <algorithm>

namespace seamap {
namespace {

// Rounds towards minus infinity (global pixels may lie left of or above the map).
int64_t FloorDiv(int64_t v, int64_t d) {
  return v >= 0 ? v / d : -((-v + d - 1) / d);
}

}  // namespace

TileRange TilesUnder(int zoom, int tile_size, int64_t x0, int64_t y0, int64_t width, int64_t height) {
  const int64_t count = int64_t{1} << zoom;
  TileRange r{FloorDiv(x0, tile_size), std::max<int64_t>(0, FloorDiv(y0, tile_size)),
              FloorDiv(x0 + width - 1, tile_size), std::min(count - 1, FloorDiv(y0 + height - 1, tile_size))};
  r.x1 = std::min(r.x1, r.x0 + count - 1);  // each tile once, however wide the box
  return r;
}

int WrapTileX(int zoom, int64_t x) {
  const int64_t count = int64_t{1} << zoom;
  return static_cast<int>(x - FloorDiv(x, count) * count);
}

void TileForecast::Add(int index, int zoom, const TileRange& tiles) {
  for (int64_t ty = tiles.y0; ty <= tiles.y1; ++ty)
    for (int64_t tx = tiles.x0; tx <= tiles.x1; ++tx) {
      std::vector<int>& over = frames_over_[TileId{zoom, WrapTileX(zoom, tx), static_cast<int>(ty)}];
      // Frames come in acquisition order; keep the list sorted if they do not.
      if (!over.empty() && over.back() > index)
        over.insert(std::upper_bound(over.begin(), over.end(), index), index);
      else
        over.push_back(index);
    }
}

bool TileForecast::OverSoon(const TileId& id, int after, int horizon) const {
  auto it = frames_over_.find(id);
  if (it == frames_over_.end()) return false;
  auto next = std::upper_bound(it->second.begin(), it->second.end(), after);
  return next != it->second.end() && *next <= after + horizon;
}

}  // namespace seamap
