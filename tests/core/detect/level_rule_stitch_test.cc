// Issue 32 (stress altitude 1 m): an object larger than a tile, cut by the
// edge of every window of a level, is stitched from its cut views instead of
// lost; stretches of a long object stay cut and are dropped.
#include <gtest/gtest.h>

#include "core/detect/level_rule.h"
#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

const LatLon kOrigin{43.1, 131.9};
const std::vector<double> kSizes = {0.8, 1.5, 3.0};  // rock, anchor, pipe (largest sizes)
const std::vector<int> kWhole = {25, 23, 23};        // WholeViewZooms at zooms 25, 23

// Window wx's view at zoom 25 of the east-west extent [west_m, east_m] x [0, 0.9 m].
RawDetection Cut(int wx, int cls, double west_m, double east_m, float score) {
  const LocalFrame frame(kOrigin);
  const GlobalPixel a = LatLonToPixel(frame.ToLatLon({west_m, 0.9}), 25, 256);
  const GlobalPixel b = LatLonToPixel(frame.ToLatLon({east_m, 0.0}), 25, 256);
  RawDetection r;
  r.window = {25, wx, 0};
  r.class_id = cls;
  r.score = score;
  r.box = {a.x, a.y, b.x, b.y};
  r.truncated = true;
  return r;
}

TEST(StitchCutViews, AnObjectCutInEveryWindowIsTheUnionOfItsViews) {
  // A 0.96 m anchor: one window sees its west 0.7 m, the next its east 0.6 m.
  std::vector<RawDetection> raw = {Cut(0, 1, 0.0, 0.7, 0.8f), Cut(2, 1, 0.36, 0.96, 0.93f)};
  EXPECT_EQ(StitchCutViews(kWhole, kSizes, kOrigin.lat, 256, &raw), 1);
  EXPECT_EQ(DropCutViews(kWhole, &raw), 2);
  ASSERT_EQ(raw.size(), 1u);
  EXPECT_FALSE(raw[0].truncated);
  EXPECT_FLOAT_EQ(raw[0].score, 0.93f);
  EXPECT_EQ(raw[0].window.x, 2);  // the best view's window
  EXPECT_NEAR((raw[0].box.x1 - raw[0].box.x0) * MetersPerPixel(kOrigin.lat, 25, 256), 0.96, 0.01);
}

TEST(StitchCutViews, StretchesOfALongObjectAndLoneCutViewsStayCut) {
  std::vector<RawDetection> raw = {
      Cut(0, 1, 0.0, 1.3, 0.8f), Cut(2, 1, 0.9, 2.5, 0.7f),   // a pipe's stretches called anchor: 2.5 m > 1.25 x 1.5
      Cut(4, 0, 5.0, 5.3, 0.9f),                              // a lone cut rock
      Cut(6, 2, 8.0, 9.0, 0.9f), Cut(6, 2, 8.5, 9.5, 0.9f)};  // two boxes of one window: not two views
  EXPECT_EQ(StitchCutViews(kWhole, kSizes, kOrigin.lat, 256, &raw), 0);
  EXPECT_EQ(raw.size(), 5u);
  // A class without a whole view keeps its cut views and is not stitched.
  std::vector<RawDetection> unknown = {Cut(0, 1, 0.0, 0.7, 0.8f), Cut(2, 1, 0.36, 0.96, 0.93f)};
  EXPECT_EQ(StitchCutViews({25, -1, 23}, kSizes, kOrigin.lat, 256, &unknown), 0);
  // Nor at the level where the class is seen whole (25 for anchors here).
  EXPECT_EQ(StitchCutViews({25, 25, 23}, kSizes, kOrigin.lat, 256, &unknown), 0);
  // Nor a class larger than a window at that level (a 3 m pipe at zoom 25, windows of 2.6 m).
  std::vector<RawDetection> pipe = {Cut(0, 2, 0.0, 0.7, 0.8f), Cut(2, 2, 0.36, 0.96, 0.93f)};
  EXPECT_EQ(StitchCutViews(kWhole, kSizes, kOrigin.lat, 256, &pipe), 0);
}

}  // namespace
}  // namespace seamap
