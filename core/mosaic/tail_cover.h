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

// The FrameWarper::kTail* bits of the side-edge halves (the top corner down
// to the middle row, the middle row down to the bottom corner: where tails
// lie) that `others` hold `margin` map pixels inside. A margin wider than
// the others' own side-edge strips keeps out frames that would leave the
// same place to a tail of theirs: neighbours of the same line wobbling
// sideways would otherwise count, and their tails wait for each other.
unsigned CoveredSides(const MapFootprint& own, const std::vector<const MapFootprint*>& others, double margin);

}  // namespace seamap
