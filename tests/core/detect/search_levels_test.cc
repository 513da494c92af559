#include "core/detect/search_levels.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/detect/detection_run.h"
#include "core/tiles/tile_codec.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

// The shipped model's largest sizes per class (tyre, crate, pipe, anchor, rock).
const std::vector<double> kShippedSizes = {1.0, 1.2, 3.0, 1.5, 0.8};
constexpr double kLat = 43.1;  // the simulator's origin

TEST(SearchLevels, ZoomFittingSizeIsTheTileSideNearestByRatio) {
  // 256 px tiles at 43.1 N: z 23 is 3.49 m, z 25 0.87 m.
  EXPECT_EQ(ZoomFittingSize(3.0, kLat, 256), 23);
  EXPECT_EQ(ZoomFittingSize(0.8, kLat, 256), 25);
  EXPECT_EQ(ZoomFittingSize(1.5, kLat, 256), 24);
  // A tile's ground does not depend on its pixels.
  EXPECT_EQ(ZoomFittingSize(3.0, kLat, 512), 23);
}

// The levels where the shipped model's classes have their trained sizes
// (zooms 25 and 23), whatever the base zoom the survey's altitude gave.
TEST(SearchLevels, ShippedClassesAreSearchedAtTheirTrainedScalesAtAnyAltitude) {
  EXPECT_EQ(ScaleMatchedZooms(kShippedSizes, 25, 10, kLat, 256), (std::vector<int>{25, 23}));  // 2 m
  EXPECT_EQ(ScaleMatchedZooms(kShippedSizes, 26, 10, kLat, 256), (std::vector<int>{25, 23}));  // 1 m
  // 3.5 m: base 24; the finer level is cut from base tiles scaled up 2x.
  EXPECT_EQ(ScaleMatchedZooms(kShippedSizes, 24, 10, kLat, 256), (std::vector<int>{25, 23}));
  // Higher still: never more than 2x up-scaling; never below the map's min zoom.
  EXPECT_EQ(ScaleMatchedZooms(kShippedSizes, 23, 10, kLat, 256), (std::vector<int>{23}));
  EXPECT_EQ(ScaleMatchedZooms(kShippedSizes, 25, 24, kLat, 256), (std::vector<int>{25}));
  // Unknown sizes: nothing (ChooseZooms falls back to DefaultZooms).
  EXPECT_TRUE(ScaleMatchedZooms({0, 0}, 25, 10, kLat, 256).empty());
  // One size: one level; a 0.3 m class adds a finer level 2 zooms up.
  EXPECT_EQ(ScaleMatchedZooms({0, 3.0}, 25, 10, kLat, 256), (std::vector<int>{23}));
  EXPECT_EQ(ScaleMatchedZooms({3.0, 0.3}, 28, 10, kLat, 256), (std::vector<int>{27, 25, 23}));
  // Further north a zoom's tile holds less ground: the levels follow the metres, not the zoom.
  EXPECT_EQ(ScaleMatchedZooms(kShippedSizes, 25, 10, 70.0, 256), (std::vector<int>{24, 22}));
}

TEST(SearchLevels, ChooseZoomsFollowsTheModelsSizesNotTheBaseZoom) {
  YoloModelInfo model;
  model.class_sizes_m = kShippedSizes;
  // Before: base 24 searched 24 and 22 (DefaultZooms counts down from the base), a scale the model never saw.
  EXPECT_EQ(ChooseZooms(std::nullopt, "--zooms", 10, 24, kLat, 256, model), (std::vector<int>{25, 23}));
  EXPECT_EQ(ChooseZooms(std::nullopt, "--zooms", 10, 25, kLat, 256, model), (std::vector<int>{25, 23}));
  // Sizes unknown: as before.
  model.class_sizes_m = {0, 0};
  EXPECT_EQ(ChooseZooms(std::nullopt, "--zooms", 10, 24, kLat, 256, model), (std::vector<int>{24, 22}));
  // --zooms names levels the map has, or the one above its base.
  EXPECT_EQ(ChooseZooms(std::vector<int>{23, 25}, "--zooms", 10, 24, kLat, 256, model), (std::vector<int>{25, 23}));
  EXPECT_THROW(ChooseZooms(std::vector<int>{26}, "--zooms", 10, 24, kLat, 256, model), InputError);
}

cv::Mat Gradient(int tile_size) {
  cv::Mat t(tile_size, tile_size, CV_8UC2);
  for (int y = 0; y < tile_size; ++y)
    for (int x = 0; x < tile_size; ++x) t.at<cv::Vec2b>(y, x) = cv::Vec2b((x + 3 * y) % 256, x < 200 ? 255 : 0);
  return t;
}

TEST(SearchLevels, OverzoomedTileIsTheParentsQuarterScaledUp) {
  const cv::Mat parent = Gradient(256);
  const auto child = OverzoomedTile({25, 2 * 7 + 1, 2 * 9}, parent, 256);  // east, north quarter
  ASSERT_TRUE(child);
  ASSERT_EQ(child->size(), cv::Size(256, 256));
  ASSERT_EQ(child->type(), CV_8UC2);
  cv::Mat expected;
  cv::resize(parent(cv::Rect(128, 0, 128, 128)), expected, cv::Size(256, 256), 0, 0, cv::INTER_LINEAR);
  EXPECT_EQ(cv::norm(*child, expected, cv::NORM_INF), 0);
  // The alpha edge (x = 200 in the parent) lands at 2 x (200 - 128).
  EXPECT_EQ(child->at<cv::Vec2b>(10, 100)[1], 255);
  EXPECT_EQ(child->at<cv::Vec2b>(10, 160)[1], 0);
  EXPECT_FALSE(OverzoomedTile({25, 0, 0}, std::nullopt, 256));
  EXPECT_FALSE(OverzoomedTile({25, 0, 0}, cv::Mat(128, 128, CV_8UC2), 256));
  EXPECT_EQ(ChildTiles({24, 3, 5}), (std::vector<TileId>{{25, 6, 10}, {25, 7, 10}, {25, 6, 11}, {25, 7, 11}}));
}

// A map whose finest zoom is 24: the windows of zoom 25 cover its tiles' children
// and are composed from them, scaled up.
TEST(SearchLevels, StoreWindowsOneZoomAboveTheMapAreCutFromItsTiles) {
  testing::TempDir dir;
  auto store = OpenTileStore((dir / "map").string(), "png", true);
  const cv::Mat tile = Gradient(256);
  store->PutTile({24, 10, 20}, EncodeTile(tile, TileEncoding{}));
  store->PutTile({23, 5, 10}, EncodeTile(tile, TileEncoding{}));
  const std::vector<WindowKey> windows = MapWindows(*store, {25, 23}, 256, 24);
  // Children 20..21 x 40..41: windows starting at 18 or 20 on each axis (4), plus zoom 23's (x 4, y 8 or 10).
  int z25 = 0;
  for (const WindowKey& w : windows) z25 += w.z == 25;
  EXPECT_EQ(z25, 4);
  EXPECT_EQ(windows.size(), 6u);
  // Without the scaled-up level (stored zoom 25), zoom 25 has no tile here.
  EXPECT_EQ(MapWindows(*store, {25, 23}, 256).size(), 2u);

  const TileReader read = StoreReader(*store, 24);
  const auto child = read({25, 21, 40});
  ASSERT_TRUE(child);
  cv::Mat expected;
  cv::resize(tile(cv::Rect(128, 0, 128, 128)), expected, cv::Size(256, 256), 0, 0, cv::INTER_LINEAR);
  EXPECT_EQ(cv::norm(*child, expected, cv::NORM_INF), 0);
  EXPECT_FALSE(read({25, 23, 40}));  // no parent
  EXPECT_TRUE(read({24, 10, 20}));   // stored tiles as they are
  double painted = 0;
  ComposeWindow({25, 20, 40}, 256, read, &painted);
  // Two rows of children: the west one whole, the east one up to 2 x (200 - 128) px (the parent's alpha).
  EXPECT_NEAR(painted, 2 * 256 * (256 + 144) / (768.0 * 768), 0.005);
}

}  // namespace
}  // namespace seamap
