// Issue 32: a long object seen whole at a coarse level and in pieces at a
// finer one (where it does not fit a window) keeps its whole box, centre and
// size; objects seen the same size at both levels keep the finer box.
#include <gtest/gtest.h>

#include "core/detect/merge.h"
#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

const std::vector<std::string> kNames = {"pipe", "rock"};
const LatLon kOrigin{43.1, 131.9};

// A box of width_m x height_m centred east_m, north_m, as window (z, wx, wy) sees it.
RawDetection Seen(int z, int wx, int wy, int index, float score, double east_m, double north_m, double width_m,
                  double height_m) {
  const LocalFrame frame(kOrigin);
  const GlobalPixel c = LatLonToPixel(frame.ToLatLon({east_m, north_m}), z, 256);
  const double mpp = MetersPerPixel(kOrigin.lat, z, 256);
  RawDetection r;
  r.window = {z, wx, wy};
  r.index = index;
  r.score = score;
  r.box = {c.x - width_m / mpp / 2, c.y - height_m / mpp / 2, c.x + width_m / mpp / 2, c.y + height_m / mpp / 2};
  return r;
}

TEST(MergePiece, APieceAtTheFinerLevelGivesWayToTheWholeObject) {
  const LocalFrame frame(kOrigin);
  // A 3 m pipe lying north-south at (5, 4): whole at zoom 23 (score 0.91), a
  // 1.6 m stretch of its north end boxed uncut at zoom 25 (0.92).
  const std::vector<RawDetection> raw = {Seen(23, 0, 0, 0, 0.91f, 5.0, 4.0, 0.3, 3.0),
                                         Seen(25, 0, 0, 0, 0.92f, 5.0, 4.7, 0.3, 1.6)};
  const auto out = MergeDetections(raw, kNames, 256, frame);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].zoom, 23);
  EXPECT_NEAR(out[0].position_m.east, 5.0, 0.01);
  EXPECT_NEAR(out[0].position_m.north, 4.0, 0.01);  // the piece's centre is 70 cm north
  EXPECT_NEAR(out[0].size_m[1], 3.0, 0.01);
  EXPECT_FLOAT_EQ(out[0].score, 0.92f);
  EXPECT_EQ(out[0].levels, (std::vector<int>{25, 23}));
}

TEST(MergePiece, TheSameObjectAtBothLevelsKeepsTheFinerBox) {
  const LocalFrame frame(kOrigin);
  // A rock boxed a little larger at the coarse level (1.25 times the area): not a piece.
  const std::vector<RawDetection> raw = {Seen(23, 0, 0, 0, 0.9f, 1.0, 1.0, 0.56, 0.56),
                                         Seen(25, 0, 0, 0, 0.8f, 1.0, 1.0, 0.5, 0.5)};
  const auto out = MergeDetections(raw, kNames, 256, frame);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].zoom, 25);
  EXPECT_NEAR(out[0].size_m[0], 0.5, 0.01);
}

TEST(MergePiece, ACutContainerIsNoRepresentative) {
  const LocalFrame frame(kOrigin);
  RawDetection whole_but_cut = Seen(23, 0, 0, 0, 0.9f, 5.0, 4.0, 0.3, 3.0);
  whole_but_cut.truncated = true;
  const auto out = MergeDetections({whole_but_cut, Seen(25, 0, 0, 0, 0.8f, 5.0, 4.7, 0.3, 1.6)}, kNames, 256, frame);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].zoom, 25);
}

}  // namespace
}  // namespace seamap
