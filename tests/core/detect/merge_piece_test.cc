// Issue 32: a long object seen whole at a coarse level and in pieces at a
// finer one (where it does not fit a window) keeps its whole box, centre and
// size; objects seen the same size at both levels keep the finer box.
#include <gtest/gtest.h>

#include "core/detect/level_rule.h"
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

TEST(MergePiece, AClassLargerThanAFineWindowIsRepresentedWhereItFits) {
  // The shipped classes' largest sizes (tyre, crate, pipe, anchor, rock) at
  // 43 N: windows are 2.6 m at zoom 25, 10.5 m at 23; only the 3 m pipe
  // needs 23.
  EXPECT_EQ(RepresentativeZooms({1.0, 1.2, 3.0, 1.5, 0.8, 0}, {25, 23}, 43.1, 256),
            (std::vector<int>{25, 25, 23, 25, 25, -1}));
  EXPECT_EQ(RepresentativeZooms({3.0}, {25}, 43.1, 256), (std::vector<int>{-1}));
  const LocalFrame frame(kOrigin);
  // A 2.4 m pipe lying diagonally: boxed at zoom 25 a little short and 14 cm
  // off (not a piece by area), whole at 23.
  const std::vector<RawDetection> raw = {Seen(23, 0, 0, 0, 0.8f, 5.0, 4.0, 1.7, 1.7),
                                         Seen(25, 0, 0, 0, 0.94f, 5.1, 4.1, 1.5, 1.5)};
  MergeOptions options;
  EXPECT_EQ(MergeDetections(raw, kNames, 256, frame, options)[0].zoom, 25);  // finest first, as before
  options.representative_zoom = {23, 25};                                    // pipe, rock
  const auto out = MergeDetections(raw, kNames, 256, frame, options);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].zoom, 23);
  EXPECT_NEAR(out[0].position_m.east, 5.0, 0.01);
  // A cluster seen only at the finer level keeps that box.
  const auto fine_only = MergeDetections({raw[1]}, kNames, 256, frame, options);
  ASSERT_EQ(fine_only.size(), 1u);
  EXPECT_EQ(fine_only[0].zoom, 25);
}

}  // namespace
}  // namespace seamap
