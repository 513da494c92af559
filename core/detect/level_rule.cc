#include "core/detect/level_rule.h"

#include <algorithm>

#include "core/geo/web_mercator.h"

namespace seamap {

std::vector<int> WholeViewZooms(const std::vector<double>& class_sizes_m, const std::vector<int>& zooms, double lat_deg,
                                int tile_size) {
  std::vector<int> out(class_sizes_m.size(), -1);
  for (size_t c = 0; c < class_sizes_m.size(); ++c) {
    if (!(class_sizes_m[c] > 0)) continue;
    for (int z : zooms)
      if (class_sizes_m[c] / MetersPerPixel(lat_deg, z, tile_size) <= tile_size) out[c] = std::max(out[c], z);
  }
  return out;
}

int DropCutViews(const std::vector<int>& whole_view_zoom, std::vector<RawDetection>* raw) {
  const auto cut_piece = [&](const RawDetection& r) {
    return r.truncated && r.class_id >= 0 && r.class_id < static_cast<int>(whole_view_zoom.size()) &&
           whole_view_zoom[r.class_id] >= 0;
  };
  const auto end = std::remove_if(raw->begin(), raw->end(), cut_piece);
  const int dropped = static_cast<int>(raw->end() - end);
  raw->erase(end, raw->end());
  return dropped;
}

}  // namespace seamap
