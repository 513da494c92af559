#include "core/detect/window_grid.h"

#include <algorithm>

namespace seamap {

int WindowTiles(int tile_size) {
  return tile_size >= 512 ? 2 : 3;
}

std::vector<WindowKey> WindowsHolding(const TileId& t, int n) {
  const int step = n - 1, max_start = (1 << t.z) - 1;
  const auto starts = [&](int i) {
    std::vector<int> s;
    for (int k = (i / step) * step; k >= 0 && k > i - n; k -= step)
      if (k <= max_start) s.push_back(k);
    return s;
  };
  std::vector<WindowKey> out;
  for (int y : starts(t.y))
    for (int x : starts(t.x)) out.push_back({t.z, x, y});
  return out;
}

std::vector<WindowKey> WindowsHoldingAny(const std::vector<TileId>& tiles, int n) {
  std::vector<WindowKey> out;
  for (const TileId& t : tiles)
    for (const WindowKey& w : WindowsHolding(t, n)) out.push_back(w);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

bool SearchableAt(double size_m, double m_per_px, int tile_size, int input_px) {
  const double r = static_cast<double>(input_px) / (WindowTiles(tile_size) * tile_size);
  return size_m * r / m_per_px >= 16 && size_m / m_per_px <= tile_size;
}

std::vector<int> DefaultZooms(int base_zoom, int min_zoom, double largest_size_m, double lat, int tile_size,
                              int input_px) {
  std::vector<int> zooms;
  for (int z = base_zoom; z >= min_zoom; z -= 2) {
    zooms.push_back(z);
    if (largest_size_m / MetersPerPixel(lat, z, tile_size) <= tile_size) break;  // fits the overlap here
  }
  (void)input_px;
  return zooms;
}

}  // namespace seamap
