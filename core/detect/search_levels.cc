#include "core/detect/search_levels.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace seamap {

int ZoomFittingSize(double size_m, double lat_deg, int tile_size) {
  // Tile sides halve per zoom: the nearest by ratio is the rounded log2.
  const double side0_m = MetersPerPixel(lat_deg, 0, tile_size) * tile_size;
  return static_cast<int>(std::lround(std::log2(side0_m / size_m)));
}

std::vector<int> ScaleMatchedZooms(const std::vector<double>& class_sizes_m, int base_zoom, int min_zoom,
                                   double lat_deg, int tile_size) {
  double smallest = 0, largest = 0;
  for (double s : class_sizes_m)
    if (s > 0) {
      smallest = smallest > 0 ? std::min(smallest, s) : s;
      largest = std::max(largest, s);
    }
  if (largest <= 0) return {};
  const int coarse = ZoomFittingSize(largest, lat_deg, tile_size);
  const int fine = std::max(coarse, ZoomFittingSize(smallest, lat_deg, tile_size));
  std::vector<int> zooms;
  for (int z = coarse + 2 * ((fine - coarse + 1) / 2); z >= coarse; z -= 2)
    if (z <= base_zoom + 1 && z >= min_zoom) zooms.push_back(z);
  return zooms;
}

std::optional<cv::Mat> OverzoomedTile(const TileId& id, const std::optional<cv::Mat>& parent, int tile_size) {
  if (!parent || parent->empty() || parent->rows != tile_size || parent->cols != tile_size) return std::nullopt;
  const int half = tile_size / 2;
  const cv::Rect quarter((id.x & 1) * half, (id.y & 1) * half, half, half);
  cv::Mat out;
  cv::resize((*parent)(quarter), out, cv::Size(tile_size, tile_size), 0, 0, cv::INTER_LINEAR);
  return out;
}

std::vector<TileId> ChildTiles(const TileId& parent) {
  std::vector<TileId> out;
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) out.push_back({parent.z + 1, 2 * parent.x + dx, 2 * parent.y + dy});
  return out;
}

}  // namespace seamap
