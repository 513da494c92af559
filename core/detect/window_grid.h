#pragma once
// The fixed global grid of search windows (n x n tiles of one zoom, starting
// at tile indices that are multiples of n-1, overlapping by one tile) and the
// rule choosing which zooms to search for objects of a given size.
#include <vector>

#include "core/geo/web_mercator.h"

namespace seamap {

struct WindowKey {
  int z = 0;
  int x = 0, y = 0;  // tile index of the north-west tile: multiples of n-1
  bool operator<(const WindowKey& o) const { return z != o.z ? z > o.z : (y != o.y ? y < o.y : x < o.x); }
  bool operator==(const WindowKey& o) const { return z == o.z && x == o.x && y == o.y; }
};

// Tiles per window side: 3 for 256 px tiles (768 px), 2 for 512 px (1024 px).
int WindowTiles(int tile_size);

// The windows holding tile t (4 for n = 3 at inner tiles, fewer at the edge of the world).
std::vector<WindowKey> WindowsHolding(const TileId& t, int n);

// Every window holding any of `tiles` (one zoom or several), sorted and unique.
std::vector<WindowKey> WindowsHoldingAny(const std::vector<TileId>& tiles, int n);

// Whether an object of `size_m` is searched at a level of `m_per_px`:
// at least 16 network pixels, and no larger than the one-tile overlap.
bool SearchableAt(double size_m, double m_per_px, int tile_size, int input_px);

// The default zooms (spec sect. 3): base, base-2, base-4, ... until the
// largest class size is searchable, never below min_zoom.
std::vector<int> DefaultZooms(int base_zoom, int min_zoom, double largest_size_m, double lat, int tile_size,
                              int input_px);

}  // namespace seamap
