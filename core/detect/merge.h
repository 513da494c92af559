#pragma once
// Merges the boxes found in overlapping windows and on several levels into
// one object each (spec sect. 8): same-class boxes that overlap in metres are
// one cluster; its representative is an uncut box of the finest level with
// the highest score, unless it is a piece of a larger uncut member (then the
// larger); a cluster covering another class's keeps the higher
// score and names the other as alt_class. Any input order gives the same result.
#include <string>
#include <vector>

#include "core/detect/box_geo.h"
#include "core/detect/recognised_object.h"
#include "core/detect/window_grid.h"

namespace seamap {

// A box as one window's search found it (after NMS), in global pixels.
struct RawDetection {
  WindowKey window;
  int index = 0;  // position in the window's output
  int class_id = 0;
  float score = 0;
  PixelBox box;
  bool truncated = false;  // touches an inner window edge
};

struct MergeOptions {
  double same_class_iou = 0.4;
  double same_class_ios = 0.7;  // intersection over the smaller box
  double cross_class_iou = 0.7;
  // An uncut box holding the representative (intersection over the smaller
  // >= same_class_ios) with at least this many times its area represents the
  // cluster instead: the smaller is a piece of it.
  double piece_area_ratio = 1.5;
  // By class id (RepresentativeZooms): boxes of levels above it represent a
  // cluster only when it has none at or below it; -1 or past the table: any.
  std::vector<int> representative_zoom;
};

std::vector<RecognisedObject> MergeDetections(std::vector<RawDetection> raw, const std::vector<std::string>& names,
                                              int tile_size, const LocalFrame& frame, const MergeOptions& options = {});

}  // namespace seamap
