#include "core/detect/level_rule.h"

#include <algorithm>
#include <map>

#include "core/detect/window_grid.h"
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

std::vector<int> RepresentativeZooms(const std::vector<double>& class_sizes_m, const std::vector<int>& zooms,
                                     double lat_deg, int tile_size) {
  std::vector<int> out(class_sizes_m.size(), -1);
  const int window_px = WindowTiles(tile_size) * tile_size;
  for (size_t c = 0; c < class_sizes_m.size(); ++c) {
    if (!(class_sizes_m[c] > 0)) continue;
    for (int z : zooms)
      if (class_sizes_m[c] / MetersPerPixel(lat_deg, z, tile_size) <= window_px) out[c] = std::max(out[c], z);
  }
  return out;
}

int StitchCutViews(const std::vector<int>& whole_view_zoom, const std::vector<double>& class_sizes_m, double lat_deg,
                   int tile_size, std::vector<RawDetection>* raw) {
  const int classes = static_cast<int>(std::min(whole_view_zoom.size(), class_sizes_m.size()));
  const int window_px = WindowTiles(tile_size) * tile_size;
  std::vector<size_t> cut;
  for (size_t i = 0; i < raw->size(); ++i) {
    const RawDetection& r = (*raw)[i];
    // At the whole-view level itself some window holds the object whole: a
    // union of cut views there is a stretch of something larger.
    // And only where the class's largest size fits a window (RepresentativeZooms): a 3 m pipe's stretches at
    // zoom 25 would unite into boxes that outrank its whole view at 23.
    if (r.truncated && r.class_id >= 0 && r.class_id < classes && whole_view_zoom[r.class_id] >= 0 &&
        r.window.z > whole_view_zoom[r.class_id] &&
        class_sizes_m[r.class_id] / MetersPerPixel(lat_deg, r.window.z, tile_size) <= window_px)
      cut.push_back(i);
  }
  const auto area = [](const PixelBox& b) { return std::max(0.0, b.x1 - b.x0) * std::max(0.0, b.y1 - b.y0); };
  const auto ios = [&](const PixelBox& a, const PixelBox& b) {
    const double w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0), h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
    const double smaller = std::min(area(a), area(b));
    return w > 0 && h > 0 && smaller > 0 ? w * h / smaller : 0.0;
  };
  std::vector<size_t> parent(cut.size());
  for (size_t k = 0; k < parent.size(); ++k) parent[k] = k;
  const auto find = [&](size_t k) {
    while (parent[k] != k) k = parent[k] = parent[parent[k]];
    return k;
  };
  for (size_t a = 0; a < cut.size(); ++a)  // a level's cut views are few: pairs are cheap
    for (size_t b = a + 1; b < cut.size(); ++b) {
      const RawDetection &p = (*raw)[cut[a]], &q = (*raw)[cut[b]];
      if (p.class_id == q.class_id && p.window.z == q.window.z && !(p.window == q.window) && ios(p.box, q.box) >= 0.3)
        parent[find(a)] = find(b);
    }
  std::map<size_t, std::vector<size_t>> groups;
  for (size_t k = 0; k < cut.size(); ++k) groups[find(k)].push_back(cut[k]);
  int made = 0;
  for (const auto& [root, members] : groups) {
    if (members.size() < 2) continue;
    RawDetection u = (*raw)[members[0]];
    for (size_t i : members) {
      const RawDetection& r = (*raw)[i];
      u.box = {std::min(u.box.x0, r.box.x0), std::min(u.box.y0, r.box.y0), std::max(u.box.x1, r.box.x1),
               std::max(u.box.y1, r.box.y1)};
      if (r.score > u.score) u.score = r.score, u.window = r.window, u.index = r.index;
    }
    const double side_m =
        std::max(u.box.x1 - u.box.x0, u.box.y1 - u.box.y0) * MetersPerPixel(lat_deg, u.window.z, tile_size);
    if (side_m > 1.25 * class_sizes_m[u.class_id]) continue;
    u.truncated = false;
    raw->push_back(u);  // the cut views themselves are dropped by DropCutViews
    ++made;
  }
  return made;
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
