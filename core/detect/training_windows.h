#pragma once
// The operator's review as training data (issue 32): the recogniser's windows
// (the levels it searches, n x n tiles starting at multiples of n-1, composed
// by ComposeWindow) with boxes from the mission's detections:
//  - labels: confirmed recogniser detections and operator marks with a box
//    (not rejected), by their (possibly corrected) class;
//  - negatives: rejected recogniser detections. Their windows are written,
//    their boxes are no label (the network learns they are background);
//  - ignored: unconfirmed detections and stereo sightings (nobody said what
//    they are), and labels less than half inside a window. Their pixels are
//    painted grey 114 (what the recogniser sees where the map has no data),
//    so they teach neither "object" nor "background"; a window where such a
//    box overlaps a label is not written (masking would cut the label). An
//    operator's point mark (no box, no extent) keeps every window holding it
//    out.
// Written windows: every window holding the centre of a label or a negative,
// plus up to `empty_per_labelled` x as many windows of the same mission and
// levels that touch no detection at all (seeded sample).
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/detect/tile_detector.h"
#include "core/detect/window_grid.h"
#include "core/tiles/mission_records.h"

namespace seamap {

// A box in one window's own pixels (0..side), x right, y down.
struct WindowBox {
  std::string class_name;
  std::array<double, 4> box_px{};  // x0, y0, x1, y1
  std::string source;              // "confirmed" | "operator" (labels); "rejected" (negatives)
  int64_t id = 0;                  // the detection's id in its mission
};

struct TrainingWindow {
  WindowKey key;
  std::vector<WindowBox> labels, negatives;
  std::vector<cv::Rect> masked_px;  // painted grey 114 (ignored objects)
};

// How a mission's detection takes part.
enum class TrainingRole { kLabel, kNegative, kIgnored, kPointIgnored };
TrainingRole RoleOf(const Detection& d);

struct TrainingPlanOptions {
  std::vector<int> zooms;  // the recogniser's levels
  int tile_size = 256;
  double empty_per_labelled = 1;  // empty windows per window with a label or a negative
  uint64_t seed = 1;              // of the empty windows' sample
};

struct TrainingPlan {
  std::vector<TrainingWindow> windows;  // labelled first (by key), then the empty sample
  int labelled = 0, empty = 0;
  int skipped_overlap = 0;  // windows left out: an ignored box over a label
  int ignored = 0;          // detections that are neither label nor negative
};

// Plans one mission's windows. `painted_fraction` tells how much of a window
// the map covers (windows under 2 % are skipped, as the recogniser skips
// them); `candidates` are every window of the levels (for the empty sample).
TrainingPlan PlanTrainingWindows(const std::vector<Detection>& detections, const TrainingPlanOptions& options,
                                 const std::vector<WindowKey>& candidates,
                                 const std::function<double(const WindowKey&)>& painted_fraction);

// The window's pixels as the recogniser composes them, ignored boxes grey.
cv::Mat ComposeTrainingWindow(const TrainingWindow& w, int tile_size, const TileReader& read);

// One YOLO label line per box: "class_id cx cy w h" normalised to the window side.
std::string YoloLabelText(const std::vector<WindowBox>& labels, const std::vector<std::string>& classes, int side_px);

}  // namespace seamap
