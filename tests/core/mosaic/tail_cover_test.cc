#include "core/mosaic/tail_cover.h"

#include <gtest/gtest.h>

#include "core/mosaic/frame_warper.h"

namespace seamap {
namespace {

// A north-up frame 100 x 80 map pixels with its top-left corner at (x, y).
MapFootprint Frame(double x, double y) {
  return MapFootprint(
      {cv::Point2d(x, y), cv::Point2d(x + 100, y), cv::Point2d(x + 100, y + 80), cv::Point2d(x, y + 80)});
}

TEST(TailCover, SideHalvesAreCoveredWhereOtherFramesHoldThem) {
  constexpr unsigned kLowerLeft = FrameWarper::kTailLowerLeft, kLowerRight = FrameWarper::kTailLowerRight;
  constexpr unsigned kUpperLeft = FrameWarper::kTailUpperLeft, kUpperRight = FrameWarper::kTailUpperRight;
  const MapFootprint own = Frame(0, 0);
  const MapFootprint right_line = Frame(60, 10), left_line = Frame(-60, 10), ahead = Frame(0, 30);
  const MapFootprint short_right = Frame(60, -50);  // holds the right edge down to a third of it
  const MapFootprint touching = Frame(99, 0);       // the right edge 1 px inside: not by the margin
  EXPECT_EQ(CoveredSides(own, {}, 2), 0u);
  // The lines start 10 px lower: the edges' lower halves only.
  EXPECT_EQ(CoveredSides(own, {&right_line}, 2), kLowerRight);
  EXPECT_EQ(CoveredSides(own, {&left_line}, 2), kLowerLeft);
  EXPECT_EQ(CoveredSides(own, {&left_line, &right_line}, 2), kLowerLeft | kLowerRight);
  EXPECT_EQ(CoveredSides(own, {&short_right}, 2), 0u);
  EXPECT_EQ(CoveredSides(own, {&touching}, 2), 0u);
  // A frame of the same line ahead covers neither side: its edges are the same lines.
  EXPECT_EQ(CoveredSides(own, {&ahead}, 2), 0u);
  // Frames sharing an edge between them cover it; the upper one alone holds the upper half.
  const MapFootprint upper = Frame(60, -15), lower = Frame(60, 60);
  EXPECT_EQ(CoveredSides(own, {&upper}, 2), kUpperRight);
  EXPECT_EQ(CoveredSides(own, {&lower}, 2), 0u);
  EXPECT_EQ(CoveredSides(own, {&upper, &lower}, 2), kUpperRight | kLowerRight);
  const MapFootprint upper_left = Frame(-60, -15);
  EXPECT_EQ(CoveredSides(own, {&upper_left, &left_line, &upper, &lower}, 2),
            kUpperLeft | kLowerLeft | kUpperRight | kLowerRight);
  // A neighbour of the same line reaching 5 px further left holds the left
  // edge by 5 px: enough for a margin of 2, not for one past a side strip of 7.
  const MapFootprint wobble = Frame(-5, -20);
  EXPECT_EQ(CoveredSides(own, {&wobble}, 2), kUpperLeft);
  EXPECT_EQ(CoveredSides(own, {&wobble}, 9), 0u);
}

TEST(TailCover, InsideDoesNotDependOnTheCornersTurn) {
  const MapFootprint forward = Frame(0, 0);
  const MapFootprint backward({cv::Point2d(0, 0), cv::Point2d(0, 80), cv::Point2d(100, 80), cv::Point2d(100, 0)});
  for (const MapFootprint* f : {&forward, &backward}) {
    EXPECT_TRUE(f->HoldsInside({50, 40}, 2));
    EXPECT_TRUE(f->HoldsInside({3, 40}, 2));
    EXPECT_FALSE(f->HoldsInside({1, 40}, 2));
    EXPECT_FALSE(f->HoldsInside({50, 81}, 0));
    EXPECT_FALSE(f->HoldsInside({-5, -5}, 0));
  }
}

}  // namespace
}  // namespace seamap
