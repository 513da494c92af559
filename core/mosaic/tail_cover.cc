#include "core/mosaic/tail_cover.h"

#include "core/mosaic/frame_warper.h"

namespace seamap {

MapFootprint::MapFootprint(const std::array<cv::Point2d, 4>& c) : corners(c) {
  double area = 0;  // shoelace: its sign is the corners' turning direction
  for (int k = 0; k < 4; ++k) area += c[k].x * c[(k + 1) % 4].y - c[(k + 1) % 4].x * c[k].y;
  turn_ = area > 0 ? 1 : -1;
}

bool MapFootprint::HoldsInside(const cv::Point2d& p, double margin) const {
  for (int k = 0; k < 4; ++k) {
    const cv::Point2d a = corners[k], e = corners[(k + 1) % 4] - a;
    const double cross = turn_ * (e.x * (p.y - a.y) - e.y * (p.x - a.x));  // |e| times the distance
    if (cross <= 0 || cross * cross < margin * margin * e.dot(e)) return false;
  }
  return true;
}

unsigned CoveredSides(const MapFootprint& own, const std::vector<const MapFootprint*>& others, double margin) {
  constexpr unsigned kBits[2][2] = {{FrameWarper::kTailUpperLeft, FrameWarper::kTailLowerLeft},
                                    {FrameWarper::kTailUpperRight, FrameWarper::kTailLowerRight}};
  unsigned out = 0;
  for (int side = 0; side < 2; ++side) {
    // Straight between the corners: a prediction, so the lens's slight bow does not matter.
    const cv::Point2d top = own.corners[side == 0 ? 0 : 1], bottom = own.corners[side == 0 ? 3 : 2];
    for (int half = 0; half < 2; ++half) {
      bool all = true;
      for (int i = 0; i <= 8 && all; ++i) {
        const cv::Point2d p = top + (bottom - top) * (0.5 * half + i / 16.0);
        bool held = false;
        for (const MapFootprint* o : others) held = held || o->HoldsInside(p, margin);
        all = held;
      }
      if (all) out |= kBits[side][half];
    }
  }
  return out;
}

}  // namespace seamap
