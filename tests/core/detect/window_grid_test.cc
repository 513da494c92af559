#include "core/detect/window_grid.h"

#include <gtest/gtest.h>

#include <random>

namespace seamap {
namespace {

TEST(WindowGrid, WindowsStartAtMultiplesOfNMinusOne) {
  EXPECT_EQ(WindowTiles(256), 3);
  EXPECT_EQ(WindowTiles(512), 2);
  // Tile 4 lies in windows starting at 2 and 4 on each axis; tile 5 only in 4.
  auto w = WindowsHolding({20, 4, 5}, 3);
  ASSERT_EQ(w.size(), 2u);
  for (const auto& k : w) {
    EXPECT_EQ(k.y, 4);
    EXPECT_TRUE(k.x == 2 || k.x == 4);
  }
  EXPECT_EQ(WindowsHolding({20, 4, 4}, 3).size(), 4u);
  EXPECT_EQ(WindowsHolding({20, 0, 0}, 3).size(), 1u);
  EXPECT_EQ(WindowsHolding({20, 7, 7}, 2).size(), 4u);
  EXPECT_EQ(WindowsHoldingAny({{20, 4, 4}, {20, 5, 5}}, 3).size(), 4u);
}

// Any object no larger than the one-tile overlap lies whole in some window.
TEST(WindowGrid, ObjectsWithinTheOverlapLieWholeInSomeWindow) {
  std::mt19937 rng(7);
  for (int tile_size : {256, 512}) {
    const int n = WindowTiles(tile_size);
    std::uniform_real_distribution<double> pos(0, 64.0 * tile_size), size(0, tile_size);
    for (int i = 0; i < 20000; ++i) {
      const double x0 = pos(rng), y0 = pos(rng), x1 = x0 + size(rng), y1 = y0 + size(rng);
      const TileId t{12, static_cast<int>(x0 / tile_size), static_cast<int>(y0 / tile_size)};
      bool whole = false;
      for (const WindowKey& w : WindowsHolding(t, n))
        whole = whole || (x0 >= w.x * tile_size && x1 <= (w.x + n) * tile_size && y0 >= w.y * tile_size &&
                          y1 <= (w.y + n) * tile_size);
      ASSERT_TRUE(whole) << "box " << x0 << "," << y0 << " - " << x1 << "," << y1 << " tiles " << tile_size;
    }
  }
}

TEST(WindowGrid, LevelRuleFollowsTheSpecTable) {
  const double lat = 43.1;
  // z 23 searches 0.26 - 3.49 m (spec sect. 3).
  const double g23 = MetersPerPixel(lat, 23, 256);
  EXPECT_FALSE(SearchableAt(0.24, g23, 256, 640));
  EXPECT_TRUE(SearchableAt(0.28, g23, 256, 640));
  EXPECT_TRUE(SearchableAt(3.4, g23, 256, 640));
  EXPECT_FALSE(SearchableAt(3.6, g23, 256, 640));
  // Base 25, classes up to 3 m: 25 and 23; up to 4 m: down to 21; never below min zoom.
  EXPECT_EQ(DefaultZooms(25, 10, 3.0, lat, 256, 640), (std::vector<int>{25, 23}));
  EXPECT_EQ(DefaultZooms(25, 10, 4.0, lat, 256, 640), (std::vector<int>{25, 23, 21}));
  EXPECT_EQ(DefaultZooms(25, 24, 4.0, lat, 256, 640), (std::vector<int>{25}));
  EXPECT_EQ(DefaultZooms(25, 10, 0.5, lat, 256, 640), (std::vector<int>{25}));
}

}  // namespace
}  // namespace seamap
