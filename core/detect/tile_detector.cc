#include "core/detect/tile_detector.h"

#include <chrono>

#include <opencv2/imgproc.hpp>

namespace seamap {

cv::Mat ComposeWindow(const WindowKey& w, int tile_size, const TileReader& read, double* painted_fraction) {
  const int n = WindowTiles(tile_size), side = n * tile_size;
  cv::Mat out(side, side, CV_8UC3, cv::Scalar::all(114));
  int64_t painted = 0;
  const int max_index = (1 << w.z) - 1;
  for (int dy = 0; dy < n; ++dy)
    for (int dx = 0; dx < n; ++dx) {
      const TileId id{w.z, w.x + dx, w.y + dy};
      if (id.x > max_index || id.y > max_index) continue;
      const std::optional<cv::Mat> tile = read(id);
      if (!tile || tile->empty() || tile->rows != tile_size || tile->cols != tile_size) continue;
      const int colour = tile->channels() == 2 ? 1 : 3;
      for (int y = 0; y < tile_size; ++y) {
        const uint8_t* src = tile->ptr<uint8_t>(y);
        uint8_t* dst = out.ptr<uint8_t>(dy * tile_size + y) + dx * tile_size * 3;
        for (int x = 0; x < tile_size; ++x, src += colour + 1, dst += 3) {
          const int a = src[colour];
          if (!a) continue;
          ++painted;
          for (int c = 0; c < 3; ++c) {
            const int v = src[colour == 1 ? 0 : c];
            dst[c] = static_cast<uint8_t>((v * a + 114 * (255 - a) + 127) / 255);
          }
        }
      }
    }
  if (painted_fraction) *painted_fraction = static_cast<double>(painted) / (static_cast<double>(side) * side);
  return out;
}

TileDetector::TileDetector(std::shared_ptr<const YoloModelInfo> info, int tile_size, float min_score)
    : model_(std::move(info)), tile_size_(tile_size) {
  thresholds_.all = min_score;
}

TileDetector::TileDetector(std::shared_ptr<const YoloModelInfo> info, int tile_size, ScoreThresholds thresholds)
    : model_(std::move(info)), tile_size_(tile_size), thresholds_(std::move(thresholds)) {}

WindowSearch TileDetector::Search(const WindowKey& w, const TileReader& read) {
  const auto t0 = std::chrono::steady_clock::now();
  WindowSearch result;
  double painted = 0;
  const cv::Mat bgr = ComposeWindow(w, tile_size_, read, &painted);
  if (painted < 0.02) {
    result.skipped = true;
    return result;
  }
  const std::vector<YoloBox> boxes = model_.Detect(bgr, thresholds_, 0.5f, &result.dropped);
  const int side = bgr.cols;
  const double scale = MakeLetterbox(bgr.size(), model_.info().input).scale;
  const double edge_px = 2 / scale;  // 2 network pixels
  const int max_start = (1 << w.z) - WindowTiles(tile_size_);
  // An inner edge: the map goes on beyond it in a neighbouring window.
  const bool inner_w = w.x > 0, inner_n = w.y > 0, inner_e = w.x < max_start, inner_s = w.y < max_start;
  const double x0 = static_cast<double>(w.x) * tile_size_, y0 = static_cast<double>(w.y) * tile_size_;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const YoloBox& b = boxes[i];
    RawDetection r;
    r.window = w;
    r.index = static_cast<int>(i);
    r.class_id = b.class_id;
    r.score = b.score;
    r.box = {x0 + b.x0, y0 + b.y0, x0 + b.x1, y0 + b.y1};
    r.truncated = (inner_w && b.x0 <= edge_px) || (inner_n && b.y0 <= edge_px) || (inner_e && b.x1 >= side - edge_px) ||
                  (inner_s && b.y1 >= side - edge_px);
    result.found.push_back(r);
  }
  result.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

std::vector<RawDetection> WindowResults::All() const {
  std::vector<RawDetection> all;
  for (const auto& [w, found] : by_window_) all.insert(all.end(), found.begin(), found.end());
  return all;
}

}  // namespace seamap
