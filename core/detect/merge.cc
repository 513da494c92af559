#include "core/detect/merge.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace seamap {
namespace {

struct Metric {
  double w, e, s, n;
};

double Area(const Metric& a) {
  return std::max(0.0, a.e - a.w) * std::max(0.0, a.n - a.s);
}
double Intersection(const Metric& a, const Metric& b) {
  const double w = std::max(0.0, std::min(a.e, b.e) - std::max(a.w, b.w));
  const double h = std::max(0.0, std::min(a.n, b.n) - std::max(a.s, b.s));
  return w * h;
}
double Iou(const Metric& a, const Metric& b) {
  const double i = Intersection(a, b), u = Area(a) + Area(b) - i;
  return u > 0 ? i / u : 0;
}
double Ios(const Metric& a, const Metric& b) {
  const double m = std::min(Area(a), Area(b));
  return m > 0 ? Intersection(a, b) / m : 0;
}

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::vector<RecognisedObject> MergeDetections(std::vector<RawDetection> raw, const std::vector<std::string>& names,
                                              int tile_size, const LocalFrame& frame, const MergeOptions& options) {
  std::sort(raw.begin(), raw.end(), [](const RawDetection& a, const RawDetection& b) {
    return std::tie(a.window.z, a.window.y, a.window.x, a.index) <
           std::tie(b.window.z, b.window.y, b.window.x, b.index);
  });
  const int n = static_cast<int>(raw.size());
  std::vector<GeoBox> geo(n);
  std::vector<Metric> m(n);
  for (int i = 0; i < n; ++i) {
    geo[i] = ToGeo(raw[i].box, raw[i].window.z, tile_size, frame);
    m[i] = {geo[i].west_m, geo[i].east_m, geo[i].south_m, geo[i].north_m};
  }
  // Same-class clusters: candidate pairs through a grid hash of 5 m cells, or
  // larger so that no box spans more than ~8 cells a side (a model's boxes
  // the size of a window would otherwise fill millions of cells). Which
  // pairs are compared, not what they give, depends on the cell.
  double largest_m = 0;
  for (int i = 0; i < n; ++i) largest_m = std::max({largest_m, m[i].e - m[i].w, m[i].n - m[i].s});
  const double cell_m = std::max(5.0, largest_m / 8);
  std::map<std::tuple<int, long, long>, std::vector<int>> cells;
  for (int i = 0; i < n; ++i)
    for (long cx = std::lround(std::floor(m[i].w / cell_m)); cx <= std::lround(std::floor(m[i].e / cell_m)); ++cx)
      for (long cy = std::lround(std::floor(m[i].s / cell_m)); cy <= std::lround(std::floor(m[i].n / cell_m)); ++cy)
        cells[{raw[i].class_id, cx, cy}].push_back(i);
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& [cell, members] : cells)
    for (size_t a = 0; a < members.size(); ++a)
      for (size_t b = a + 1; b < members.size(); ++b) {
        const int i = members[a], j = members[b];
        if (Find(parent, i) == Find(parent, j)) continue;  // already one cluster (big cells hold many)
        if (Iou(m[i], m[j]) >= options.same_class_iou || Ios(m[i], m[j]) >= options.same_class_ios)
          parent[Find(parent, i)] = Find(parent, j);
      }
  std::map<int, std::vector<int>> clusters;  // root -> members in input order
  for (int i = 0; i < n; ++i) clusters[Find(parent, i)].push_back(i);

  struct Cluster {
    int rep;
    float score;
    std::vector<int> levels;
    bool truncated;
    std::string alt;
  };
  const auto fits_window = [&](const RawDetection& r) {
    const auto& zs = options.representative_zoom;
    return r.class_id < 0 || r.class_id >= static_cast<int>(zs.size()) || zs[r.class_id] < 0 ||
           r.window.z <= zs[r.class_id];
  };
  std::vector<Cluster> all;
  for (const auto& [root, members] : clusters) {
    Cluster c{members[0], 0, {}, true, ""};
    for (int i : members) {
      const RawDetection& r = raw[i];
      const RawDetection& best = raw[c.rep];
      // Untruncated first, then a level where the class fits a window, then
      // finest level, then highest score, then input order.
      if (std::make_tuple(!r.truncated, fits_window(r), r.window.z, r.score) >
          std::make_tuple(!best.truncated, fits_window(best), best.window.z, best.score))
        c.rep = i;
      c.score = std::max(c.score, r.score);
      c.truncated = c.truncated && r.truncated;
      if (std::find(c.levels.begin(), c.levels.end(), r.window.z) == c.levels.end()) c.levels.push_back(r.window.z);
    }
    // A piece is no representative: an uncut box contained in a member of at
    // least 1.5 times its area (a 3 m pipe seen whole at zoom 23, a 1.6 m stretch
    // of it boxed at 25, where it does not fit a window) gives way to the
    // larger, so the object keeps its centre and size (issue 32: the clear
    // stress survey's pipe was placed 67 cm off its centre).
    for (bool moved = true; moved;) {
      moved = false;
      for (int i : members) {
        const RawDetection& r = raw[i];
        if (r.truncated || Area(m[i]) < options.piece_area_ratio * Area(m[c.rep]) ||
            Ios(m[i], m[c.rep]) < options.same_class_ios)
          continue;
        c.rep = i;  // each move grows the area 1.5 times: this ends
        moved = true;
      }
    }
    std::sort(c.levels.rbegin(), c.levels.rend());
    all.push_back(c);
  }
  // Across classes: the higher score keeps the box, the other is its alt_class.
  std::sort(all.begin(), all.end(), [&](const Cluster& a, const Cluster& b) {
    return std::make_tuple(-a.score, raw[a.rep].class_id, a.rep) <
           std::make_tuple(-b.score, raw[b.rep].class_id, b.rep);
  });
  std::vector<Cluster> kept;
  for (const Cluster& c : all) {
    bool covered = false;
    for (Cluster& k : kept)
      if (raw[k.rep].class_id != raw[c.rep].class_id && Iou(m[k.rep], m[c.rep]) >= options.cross_class_iou) {
        if (k.alt.empty()) k.alt = names.at(raw[c.rep].class_id);
        covered = true;
        break;
      }
    if (!covered) kept.push_back(c);
  }
  std::vector<RecognisedObject> out;
  for (const Cluster& c : kept) {
    const RawDetection& r = raw[c.rep];
    const GeoBox& g = geo[c.rep];
    RecognisedObject o;
    o.class_id = r.class_id;
    o.class_name = names.at(r.class_id);
    o.score = c.score;
    o.zoom = r.window.z;
    o.levels = c.levels;
    o.box = g.ring;
    o.centre = g.centre;
    o.position_m = g.centre_m;
    o.size_m = {g.size_ew_m(), g.size_ns_m()};
    o.truncated = c.truncated;
    o.alt_class = c.alt;
    out.push_back(o);
  }
  std::sort(out.begin(), out.end(), [](const RecognisedObject& a, const RecognisedObject& b) {
    return std::make_tuple(-a.position_m.north, a.position_m.east, a.class_id) <
           std::make_tuple(-b.position_m.north, b.position_m.east, b.class_id);
  });
  return out;
}

}  // namespace seamap
