#include "core/mosaic/tail_cover.h"

#include <gtest/gtest.h>

#include "core/mosaic/frame_warper.h"

namespace seamap {
namespace {

// A north-up frame 100 x 80 map pixels with its top-left corner at (x, y).
MapFootprint Frame(double x, double y) {
  return MapFootprint({cv::Point2d(x, y), cv::Point2d(x + 100, y), cv::Point2d(x + 100, y + 80), cv::Point2d(x, y + 80)});
}

TEST(TailCover, SidesAreCoveredWhereOtherFramesHoldTheirLowerHalf) {
  const MapFootprint own = Frame(0, 0);
  const MapFootprint right_line = Frame(60, 10), left_line = Frame(-60, 10), ahead = Frame(0, 30);
  const MapFootprint short_right = Frame(60, -50);  // holds the right edge's upper half only
  const MapFootprint touching = Frame(99, 0);       // the right edge 1 px inside: not by the margin
  EXPECT_EQ(CoveredSides(own, {}), 0u);
  EXPECT_EQ(CoveredSides(own, {&right_line}), FrameWarper::kTailRight);
  EXPECT_EQ(CoveredSides(own, {&left_line}), FrameWarper::kTailLeft);
  EXPECT_EQ(CoveredSides(own, {&left_line, &right_line}), FrameWarper::kTailLeft | FrameWarper::kTailRight);
  EXPECT_EQ(CoveredSides(own, {&short_right}), 0u);
  EXPECT_EQ(CoveredSides(own, {&touching}), 0u);
  // A frame of the same line ahead covers neither side: its edges are the same lines.
  EXPECT_EQ(CoveredSides(own, {&ahead}), 0u);
  // Two frames sharing the lower half between them cover it; neither alone does.
  const MapFootprint upper = Frame(60, -15), lower = Frame(60, 60);
  EXPECT_EQ(CoveredSides(own, {&upper}), 0u);
  EXPECT_EQ(CoveredSides(own, {&lower}), 0u);
  EXPECT_EQ(CoveredSides(own, {&upper, &lower}), FrameWarper::kTailRight);
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
