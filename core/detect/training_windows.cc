#include "core/detect/training_windows.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include <opencv2/imgproc.hpp>

#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

constexpr double kMinInside = 0.5;     // of a label's box, for it to be a label in a window
constexpr double kMinPainted = 0.02;   // as TileDetector: emptier windows are not searched
constexpr double kMaskMargin_px = 2;   // around an ignored box (its blurred edge)
constexpr double kPointReach_m = 0.5;  // an operator's point mark keeps windows within this out

struct WindowPx {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // global pixels at one zoom
  double cx() const { return (x0 + x1) / 2; }
  double cy() const { return (y0 + y1) / 2; }
  double area() const { return std::max(0.0, x1 - x0) * std::max(0.0, y1 - y0); }
};

WindowPx Clip(const WindowPx& b, const WindowPx& w) {
  return {std::max(b.x0, w.x0), std::max(b.y0, w.y0), std::min(b.x1, w.x1), std::min(b.y1, w.y1)};
}

bool Overlaps(const WindowPx& a, const WindowPx& b) {
  return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

// The detection's box at `zoom`: its ring's bounds, else its size around its centre, else a point
// grown by kPointReach_m.
WindowPx BoxAt(const Detection& d, int zoom, int tile_size) {
  WindowPx b{1e300, 1e300, -1e300, -1e300};
  if (d.box.size() >= 4) {
    for (const LatLon& p : d.box) {
      const GlobalPixel q = LatLonToPixel(p, zoom, tile_size);
      b.x0 = std::min(b.x0, q.x), b.y0 = std::min(b.y0, q.y), b.x1 = std::max(b.x1, q.x), b.y1 = std::max(b.y1, q.y);
    }
    return b;
  }
  const GlobalPixel c = LatLonToPixel(d.position, zoom, tile_size);
  const double m_per_px = MetersPerPixel(d.position.lat, zoom, tile_size);
  const double hw = d.size_m ? (*d.size_m)[0] / 2 / m_per_px : kPointReach_m / m_per_px;
  const double hh = d.size_m ? (*d.size_m)[1] / 2 / m_per_px : kPointReach_m / m_per_px;
  return {c.x - hw, c.y - hh, c.x + hw, c.y + hh};
}

WindowPx WindowExtent(const WindowKey& w, int tile_size) {
  const int side = WindowTiles(tile_size) * tile_size;
  const double x0 = static_cast<double>(w.x) * tile_size, y0 = static_cast<double>(w.y) * tile_size;
  return {x0, y0, x0 + side, y0 + side};
}

bool HasBox(const Detection& d) {
  return d.box.size() >= 4 || d.size_m.has_value();
}

}  // namespace

TrainingRole RoleOf(const Detection& d) {
  if (d.status == "rejected") return d.source == "recogniser" ? TrainingRole::kNegative : TrainingRole::kIgnored;
  if (d.source == "recogniser") return d.status == "confirmed" ? TrainingRole::kLabel : TrainingRole::kIgnored;
  if (d.source == "operator") return HasBox(d) ? TrainingRole::kLabel : TrainingRole::kPointIgnored;
  return HasBox(d) ? TrainingRole::kIgnored : TrainingRole::kPointIgnored;  // stereo
}

TrainingPlan PlanTrainingWindows(const std::vector<Detection>& detections, const TrainingPlanOptions& options,
                                 const std::vector<WindowKey>& candidates,
                                 const std::function<double(const WindowKey&)>& painted_fraction) {
  TrainingPlan plan;
  const int T = options.tile_size, n = WindowTiles(T);
  std::vector<TrainingRole> roles;
  for (const Detection& d : detections) {
    roles.push_back(RoleOf(d));
    plan.ignored += roles.back() == TrainingRole::kIgnored || roles.back() == TrainingRole::kPointIgnored;
  }
  std::set<WindowKey> written;
  for (int z : options.zooms) {
    std::vector<WindowPx> boxes;
    for (const Detection& d : detections) boxes.push_back(BoxAt(d, z, T));
    // Windows holding the centre of a label or a negative.
    std::set<WindowKey> holding;
    for (size_t i = 0; i < detections.size(); ++i) {
      if (roles[i] != TrainingRole::kLabel && roles[i] != TrainingRole::kNegative) continue;
      const TileId tile{z, static_cast<int>(std::floor(boxes[i].cx() / T)),
                        static_cast<int>(std::floor(boxes[i].cy() / T))};
      for (const WindowKey& w : WindowsHolding(tile, n)) holding.insert(w);
    }
    for (const WindowKey& key : holding) {
      const WindowPx extent = WindowExtent(key, T);
      TrainingWindow w;
      w.key = key;
      std::vector<WindowPx> label_boxes, masks;
      bool point_inside = false;
      for (size_t i = 0; i < detections.size(); ++i) {
        const WindowPx& b = boxes[i];
        if (!Overlaps(b, extent)) continue;
        const WindowPx clipped = Clip(b, extent);
        const WindowBox local{
            detections[i].class_name,
            {clipped.x0 - extent.x0, clipped.y0 - extent.y0, clipped.x1 - extent.x0, clipped.y1 - extent.y0},
            "",
            detections[i].id};
        switch (roles[i]) {
          case TrainingRole::kLabel:
            if (clipped.area() >= kMinInside * b.area()) {
              w.labels.push_back(local);
              w.labels.back().source = detections[i].source == "operator" ? "operator" : "confirmed";
              label_boxes.push_back(clipped);
            } else {
              masks.push_back(clipped);
            }
            break;
          case TrainingRole::kNegative:
            if (b.cx() >= extent.x0 && b.cx() < extent.x1 && b.cy() >= extent.y0 && b.cy() < extent.y1) {
              w.negatives.push_back(local);
              w.negatives.back().source = "rejected";
            }
            break;
          case TrainingRole::kIgnored:
            masks.push_back(clipped);
            break;
          case TrainingRole::kPointIgnored:
            point_inside = true;
            break;
        }
      }
      if (point_inside || (w.labels.empty() && w.negatives.empty())) {
        plan.skipped_overlap += point_inside;
        continue;
      }
      bool cuts_label = false;
      for (const WindowPx& m : masks) {
        const WindowPx grown{m.x0 - kMaskMargin_px, m.y0 - kMaskMargin_px, m.x1 + kMaskMargin_px,
                             m.y1 + kMaskMargin_px};
        for (const WindowPx& l : label_boxes) cuts_label |= Overlaps(grown, l);
        const WindowPx g = Clip(grown, extent);
        const int x0 = static_cast<int>(std::floor(g.x0 - extent.x0)),
                  y0 = static_cast<int>(std::floor(g.y0 - extent.y0));
        const int x1 = static_cast<int>(std::ceil(g.x1 - extent.x0)),
                  y1 = static_cast<int>(std::ceil(g.y1 - extent.y0));
        w.masked_px.emplace_back(x0, y0, x1 - x0, y1 - y0);
      }
      if (cuts_label) {
        ++plan.skipped_overlap;
        continue;
      }
      if (painted_fraction(key) < kMinPainted) continue;
      written.insert(key);
      plan.windows.push_back(std::move(w));
    }
  }
  plan.labelled = static_cast<int>(plan.windows.size());

  // The empty sample: windows of the same levels touching no detection at all, in a seeded order.
  const long quota = std::lround(options.empty_per_labelled * plan.labelled);
  std::vector<WindowKey> pool;
  for (const WindowKey& key : candidates) {
    if (written.count(key) || std::find(options.zooms.begin(), options.zooms.end(), key.z) == options.zooms.end())
      continue;
    const WindowPx extent = WindowExtent(key, T);
    bool touched = false;
    for (const Detection& d : detections) touched = touched || Overlaps(BoxAt(d, key.z, T), extent);
    if (!touched) pool.push_back(key);
  }
  std::mt19937_64 rng(options.seed);
  for (size_t i = 0; i + 1 < pool.size(); ++i)  // Fisher-Yates with our own draws: the same sample everywhere
    std::swap(pool[i], pool[i + rng() % (pool.size() - i)]);
  for (const WindowKey& key : pool) {
    if (plan.empty >= quota) break;
    if (painted_fraction(key) < kMinPainted) continue;
    TrainingWindow w;
    w.key = key;
    plan.windows.push_back(w);
    ++plan.empty;
  }
  return plan;
}

cv::Mat ComposeTrainingWindow(const TrainingWindow& w, int tile_size, const TileReader& read) {
  cv::Mat bgr = ComposeWindow(w.key, tile_size, read, nullptr);
  const cv::Rect all(0, 0, bgr.cols, bgr.rows);
  for (const cv::Rect& r : w.masked_px) bgr(r & all).setTo(cv::Scalar::all(114));
  return bgr;
}

std::string YoloLabelText(const std::vector<WindowBox>& labels, const std::vector<std::string>& classes, int side_px) {
  std::string text;
  const double s = side_px;
  for (const WindowBox& b : labels) {
    const auto it = std::find(classes.begin(), classes.end(), b.class_name);
    char line[160];
    std::snprintf(line, sizeof line, "%d %.6f %.6f %.6f %.6f\n", static_cast<int>(it - classes.begin()),
                  (b.box_px[0] + b.box_px[2]) / 2 / s, (b.box_px[1] + b.box_px[3]) / 2 / s,
                  (b.box_px[2] - b.box_px[0]) / s, (b.box_px[3] - b.box_px[1]) / s);
    text += line;
  }
  return text;
}

}  // namespace seamap
