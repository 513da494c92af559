#include "core/detect/level_rule.h"

#include <gtest/gtest.h>

#include <memory>

#include "core/detect/detection_run.h"
#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

const LatLon kOrigin{43.1, 131.9};

// A box of `size_m` centred `east_m, north_m` from the origin, as window w at zoom z sees it.
RawDetection Seen(int z, int cls, double east_m, double north_m, double size_m, bool truncated) {
  const LocalFrame frame(kOrigin);
  const GlobalPixel c = LatLonToPixel(frame.ToLatLon({east_m, north_m}), z, 256);
  const double half = size_m / MetersPerPixel(kOrigin.lat, z, 256) / 2;
  RawDetection r;
  r.window = {z, 0, 0};
  r.class_id = cls;
  r.score = 0.9f;
  r.box = {c.x - half, c.y - half, c.x + half, c.y + half};
  r.truncated = truncated;
  return r;
}

// One tile is 0.87 m at zoom 25 and 3.49 m at zoom 23 at 43.1 N.
TEST(LevelRule, EachClassIsSeenWholeAtTheFinestLevelItsLargestSizeFits) {
  const std::vector<double> sizes = {0.8, 1.5, 3.0, 0.0, 5.0};  // rock, anchor, pipe, unknown, too large
  EXPECT_EQ(WholeViewZooms(sizes, {25, 23}, kOrigin.lat, 256), (std::vector<int>{25, 23, 23, -1, -1}));
  EXPECT_EQ(WholeViewZooms(sizes, {25}, kOrigin.lat, 256), (std::vector<int>{25, -1, -1, -1, -1}));
  EXPECT_NEAR(MetersPerPixel(kOrigin.lat, 25, 256) * 256, 0.872, 0.002);
}

TEST(LevelRule, CutViewsOfClassesSeenWholeAreDroppedOthersKept) {
  const std::vector<int> whole = {25, 23, -1};                      // rock, anchor, a class of unknown size
  std::vector<RawDetection> raw = {Seen(25, 1, 0, 0, 0.6, true),    // a pipe's piece called anchor: dropped
                                   Seen(25, 1, 3, 0, 0.6, false),   // a whole anchor: kept
                                   Seen(23, 0, 6, 0, 0.3, true),    // a cut rock at the coarse level: dropped
                                   Seen(25, 2, 9, 0, 0.6, true),    // unknown size: kept
                                   Seen(25, 7, 12, 0, 0.6, true)};  // a class outside the table: kept
  EXPECT_EQ(DropCutViews(whole, &raw), 2);
  ASSERT_EQ(raw.size(), 3u);
  EXPECT_EQ(raw[0].class_id, 1);
  EXPECT_FALSE(raw[0].truncated);
  EXPECT_EQ(raw[1].class_id, 2);
  EXPECT_EQ(raw[2].class_id, 7);
}

// Through the merge: a lone cut view of an anchor (zoom 25) is no object; the
// anchor seen whole at zoom 23 is one object, not flagged truncated; with
// keep_cut_views the piece comes back as a truncated object.
TEST(LevelRule, MergeSearchedDropsPiecesUnlessAskedToKeepThem) {
  auto model = std::make_shared<YoloModelInfo>();
  model->class_names = {"rock", "anchor", "pipe"};
  model->class_sizes_m = {0.8, 1.5, 3.0};
  DetectSettings settings;
  settings.model = model;
  settings.zooms = {25, 23};
  settings.origin = kOrigin;
  const std::vector<RawDetection> raw = {Seen(25, 1, 0, 0, 0.7, true),    // piece of a pipe, 'anchor'
                                         Seen(25, 1, 5, 0, 1.2, true),    // an anchor cut at zoom 25...
                                         Seen(23, 1, 5, 0, 1.2, false)};  // ...and whole at zoom 23
  const auto objects = MergeSearched(settings, raw, {});
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_NEAR(objects[0].position_m.east, 5.0, 0.02);
  EXPECT_FALSE(objects[0].truncated);
  EXPECT_EQ(objects[0].levels, (std::vector<int>{23}));

  settings.keep_cut_views = true;
  const auto kept = MergeSearched(settings, raw, {});
  ASSERT_EQ(kept.size(), 2u);
  int truncated = 0;
  for (const auto& o : kept) truncated += o.truncated;
  EXPECT_EQ(truncated, 1);
}

}  // namespace
}  // namespace seamap
