#include "core/mosaic/pending_tails.h"

#include <gtest/gtest.h>

namespace seamap {
namespace {

std::vector<TailPixel> Row(int64_t x0, int n) {
  std::vector<TailPixel> out;
  for (int i = 0; i < n; ++i) out.push_back({x0 + i, 10, 0.0f, 0.0f, 1});
  return out;
}

TEST(PendingTails, TakesPixelsByAreaByAgeAndByFrame) {
  PendingTails tails;
  tails.Add(1, FrameImage(), Row(0, 10));  // x 0..9
  tails.Add(2, FrameImage(), Row(5, 10));  // x 5..14
  tails.Add(3, FrameImage(), {});          // nothing to wait for: not kept
  EXPECT_EQ(tails.frames(), 2u);
  EXPECT_EQ(tails.pixels(), 20u);
  EXPECT_GT(tails.bytes(), 0u);

  // An area takes only the pixels inside it, oldest frame first.
  const auto in = tails.TakeIn(0, 0, 8, 100);
  ASSERT_EQ(in.size(), 2u);
  EXPECT_EQ(in[0].pixels.size(), 8u);
  EXPECT_EQ(in[1].pixels.size(), 3u);
  for (const auto& t : in)
    for (const TailPixel& p : t.pixels) EXPECT_LT(p.x, 8);
  EXPECT_EQ(tails.pixels(), 9u);
  EXPECT_TRUE(tails.TakeIn(0, 11, 100, 100).empty());  // below the pixels

  // By age: frame 1's last two pixels.
  const auto old = tails.TakeUpTo(1);
  ASSERT_EQ(old.size(), 1u);
  EXPECT_EQ(old[0].image, in[0].image);
  EXPECT_EQ(old[0].pixels.size(), 2u);
  EXPECT_EQ(tails.frames(), 1u);

  // By frame: the rest of frame 2.
  EXPECT_TRUE(tails.TakeFrame(in[0].image).empty());  // gone already
  EXPECT_EQ(tails.TakeFrame(in[1].image).size(), 7u);
  EXPECT_TRUE(tails.empty());
  EXPECT_EQ(tails.bytes(), 0u);
}

TEST(PendingTails, OldestAndAllComeInOrder) {
  PendingTails tails;
  for (int i = 0; i < 4; ++i) tails.Add(i, FrameImage(), Row(10 * i, 2));
  const auto first = tails.TakeOldest();
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].pixels[0].x, 0);
  const auto rest = tails.TakeAll();
  ASSERT_EQ(rest.size(), 3u);
  for (size_t i = 0; i < rest.size(); ++i) EXPECT_EQ(rest[i].pixels[0].x, 10 * static_cast<int64_t>(i + 1));
  EXPECT_TRUE(tails.empty());
  EXPECT_TRUE(tails.TakeOldest().empty());
  EXPECT_EQ(tails.bytes(), 0u);
}

}  // namespace
}  // namespace seamap
