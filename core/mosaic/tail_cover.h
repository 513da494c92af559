#pragma once
// Which side edges of a frame other frames cover: where a frame's side-edge
// tail (FrameWarper::Warp) is worth holding back, because another survey
// line, or a later frame of its own swinging back, will most likely paint it.
#include <array>
#include <vector>

#include <opencv2/core.hpp>

namespace seamap {

// A frame's footprint on the map: its raw image corners (left-top, right-top,
// right-bottom, left-bottom, as FrameWarper::Outline gives them).
struct MapFootprint {
  std::array<cv::Point2d, 4> corners;
  explicit MapFootprint(const std::array<cv::Point2d, 4>& c);
  // Whether p lies inside, at least `margin` (map pixels) from every edge.
  bool HoldsInside(const cv::Point2d& p, double margin) const;

 private:
  double turn_ = 1;  // the sign of (b - a) x (p - a) for p inside, along each edge a -> b
};

// FrameWarper::kTailLeft / kTailRight for the sides whose lower half (the
// middle row down to the bottom corner, where tails lie) `others` hold
// 2 map pixels inside.
unsigned CoveredSides(const MapFootprint& own, const std::vector<const MapFootprint*>& others);

}  // namespace seamap
