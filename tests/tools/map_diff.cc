// map_diff A B: how two maps of the same survey differ, tile by tile, at
// every zoom and layer: tiles only in one of them, and over the tiles in
// both, pixels whose coverage (alpha) differs and pixels whose value differs
// (how many, by how much). Used by scripts/golden.sh to hold a change to
// "the map is unchanged" or to a stated tolerance. Exit status 0 when the
// maps are byte-identical, 1 when they differ, 2 when one cannot be read.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <string>

#include <opencv2/core.hpp>

#include "core/mission/mission_metadata.h"
#include "core/tiles/tile_codec.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"

namespace {

struct Difference {
  int64_t tiles_a_only = 0, tiles_b_only = 0, tiles_both = 0, tiles_unequal_bytes = 0;
  int64_t pixels = 0, coverage_differs = 0, value_differs = 0, sum_abs = 0;
  int max_abs = 0;
};

void CompareTiles(const cv::Mat& a, const cv::Mat& b, Difference* d) {
  const int channels = a.channels();
  if (a.size() != b.size() || channels != b.channels()) {
    d->coverage_differs += std::max(a.total(), b.total());
    return;
  }
  const int colour = channels - 1;  // the last channel is alpha
  for (int y = 0; y < a.rows; ++y) {
    const uint8_t* pa = a.ptr<uint8_t>(y);
    const uint8_t* pb = b.ptr<uint8_t>(y);
    for (int x = 0; x < a.cols; ++x, pa += channels, pb += channels) {
      ++d->pixels;
      if ((pa[colour] == 0) != (pb[colour] == 0)) {
        ++d->coverage_differs;
        continue;
      }
      if (pa[colour] == 0) continue;
      int worst = std::abs(pa[colour] - pb[colour]);
      for (int c = 0; c < colour; ++c) worst = std::max(worst, std::abs(pa[c] - pb[c]));
      if (worst == 0) continue;
      ++d->value_differs;
      d->sum_abs += worst;
      d->max_abs = std::max(d->max_abs, worst);
    }
  }
}

Difference CompareStores(const seamap::TileStore& a, const seamap::TileStore& b) {
  Difference d;
  std::set<seamap::TileId> in_a, in_b;
  for (const auto& id : a.TileIds()) in_a.insert(id);
  for (const auto& id : b.TileIds()) in_b.insert(id);
  for (const auto& id : in_a) {
    if (!in_b.count(id)) {
      ++d.tiles_a_only;
      continue;
    }
    ++d.tiles_both;
    const auto bytes_a = a.GetTile(id), bytes_b = b.GetTile(id);
    if (*bytes_a == *bytes_b) continue;
    ++d.tiles_unequal_bytes;
    CompareTiles(seamap::WithColourChannels(seamap::DecodeTile(*bytes_a), 3),
                 seamap::WithColourChannels(seamap::DecodeTile(*bytes_b), 3), &d);
  }
  for (const auto& id : in_b)
    if (!in_a.count(id)) ++d.tiles_b_only;
  return d;
}

void Print(const std::string& layer, const Difference& d) {
  std::printf(
      "%-10s tiles %lld in both (%lld differ in bytes), %lld only in A, %lld only in B; "
      "of their pixels: coverage differs at %lld, value at %lld (mean %.2f, max %d grey levels)\n",
      layer.c_str(), static_cast<long long>(d.tiles_both), static_cast<long long>(d.tiles_unequal_bytes),
      static_cast<long long>(d.tiles_a_only), static_cast<long long>(d.tiles_b_only),
      static_cast<long long>(d.coverage_differs), static_cast<long long>(d.value_differs),
      d.value_differs ? static_cast<double>(d.sum_abs) / d.value_differs : 0.0, d.max_abs);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: map_diff A.mbtiles|DIR B.mbtiles|DIR\n");
    return 2;
  }
  try {
    auto a = seamap::OpenExistingMap(argv[1], false);
    auto b = seamap::OpenExistingMap(argv[2], false);
    bool identical = true;
    std::vector<std::string> layers{""};
    const std::vector<std::string> listed = seamap::ReadMissionMetadata(*a).LayersOrRaw();
    auto has = [&](const char* l) { return std::find(listed.begin(), listed.end(), l) != listed.end(); };
    if (has("enhanced") && has("raw")) layers.push_back("enhanced");
    for (const std::string& layer : layers) {
      std::unique_ptr<seamap::TileStore> la, lb;
      const seamap::TileStore* sa = a.get();
      const seamap::TileStore* sb = b.get();
      if (!layer.empty()) {
        la = a->OpenLayer(layer);
        lb = b->OpenLayer(layer);
        sa = la.get();
        sb = lb.get();
      }
      const Difference d = CompareStores(*sa, *sb);
      Print(layer.empty() ? "main" : layer, d);
      identical = identical && d.tiles_unequal_bytes == 0 && d.tiles_a_only == 0 && d.tiles_b_only == 0;
    }
    return identical ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "map_diff: %s\n", e.what());
    return 2;
  }
}
