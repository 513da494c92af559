#pragma once
// Searches one window of the tile pyramid: composes its n x n tiles (missing
// tiles and transparent pixels grey 114, gray replicated to three channels),
// runs the model and returns its boxes in global pixels, cut ones marked.
// Windows with under 2 % painted pixels are skipped.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/detect/merge.h"
#include "core/detect/yolo_model.h"

namespace seamap {

// A decoded tile (CV_8UC2 gray+alpha or CV_8UC4 BGRA), nullopt when there is none.
using TileReader = std::function<std::optional<cv::Mat>(const TileId&)>;

// The window's pixels as 8-bit BGR, and the fraction of them painted.
cv::Mat ComposeWindow(const WindowKey& w, int tile_size, const TileReader& read, double* painted_fraction);

struct WindowSearch {
  bool skipped = false;  // under 2 % painted
  double ms = 0;         // compose + forward + decode
  YoloDropped dropped;   // non-finite and capped boxes
  std::vector<RawDetection> found;
};

class TileDetector {
 public:
  TileDetector(std::shared_ptr<const YoloModelInfo> info, int tile_size, float min_score);
  TileDetector(std::shared_ptr<const YoloModelInfo> info, int tile_size, ScoreThresholds thresholds);
  // Not thread-safe (one net): one detector per thread.
  WindowSearch Search(const WindowKey& w, const TileReader& read);

 private:
  YoloModel model_;
  int tile_size_;
  ScoreThresholds thresholds_;
};

// The latest raw boxes of every window searched; a window searched again
// replaces its boxes (a re-finished tile updates, never duplicates).
class WindowResults {
 public:
  void Replace(const WindowKey& w, std::vector<RawDetection> found) { by_window_[w] = std::move(found); }
  std::vector<RawDetection> All() const;
  size_t windows() const { return by_window_.size(); }
  bool Has(const WindowKey& w) const { return by_window_.count(w) > 0; }

 private:
  std::map<WindowKey, std::vector<RawDetection>> by_window_;
};

}  // namespace seamap
