#include "core/detect/merge.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

const std::vector<std::string> kNames = {"tyre", "crate"};
const LatLon kOrigin{43.1, 131.9};

// A box of `size_m` centred `east_m, north_m` from the origin, as window w at zoom z sees it.
RawDetection Seen(int z, int wx, int wy, int index, int cls, float score, double east_m, double north_m, double size_m,
                  bool truncated = false) {
  const LocalFrame frame(kOrigin);
  const GlobalPixel c = LatLonToPixel(frame.ToLatLon({east_m, north_m}), z, 256);
  const double half = size_m / MetersPerPixel(kOrigin.lat, z, 256) / 2;
  RawDetection r;
  r.window = {z, wx, wy};
  r.index = index;
  r.class_id = cls;
  r.score = score;
  r.box = {c.x - half, c.y - half, c.x + half, c.y + half};
  r.truncated = truncated;
  return r;
}

TEST(Merge, OneObjectSeenByFourWindowsAndTwoLevelsIsOneDetection) {
  const LocalFrame frame(kOrigin);
  std::vector<RawDetection> raw;
  for (int i = 0; i < 4; ++i) raw.push_back(Seen(25, 2 * (i % 2), 2 * (i / 2), 0, 0, 0.6f + 0.05f * i, 3.0, 4.0, 0.8));
  raw.push_back(Seen(23, 0, 0, 3, 0, 0.95f, 3.01, 4.0, 0.82));
  const auto out = MergeDetections(raw, kNames, 256, frame);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].class_name, "tyre");
  EXPECT_EQ(out[0].zoom, 25);  // finest level represents it
  EXPECT_EQ(out[0].levels, (std::vector<int>{25, 23}));
  EXPECT_FLOAT_EQ(out[0].score, 0.95f);  // the cluster's best score
  EXPECT_NEAR(out[0].position_m.east, 3.0, 0.005);
  EXPECT_NEAR(out[0].position_m.north, 4.0, 0.005);
  EXPECT_NEAR(out[0].size_m[0], 0.8, 0.005);
  EXPECT_FALSE(out[0].truncated);
}

TEST(Merge, TwoObjectsHalfAMetreApartStayTwo) {
  const LocalFrame frame(kOrigin);
  const auto out = MergeDetections({Seen(25, 0, 0, 0, 0, 0.9f, 0, 0, 0.4), Seen(25, 0, 0, 1, 0, 0.8f, 0.5, 0, 0.4)},
                                   kNames, 256, frame);
  EXPECT_EQ(out.size(), 2u);
}

TEST(Merge, WholeBoxWinsOverTruncatedOneAndTruncatedAloneIsKept) {
  const LocalFrame frame(kOrigin);
  // The cut box is half of the whole one (intersection over the smaller = 1).
  RawDetection cut = Seen(25, 0, 0, 0, 1, 0.99f, 1.0, 1.0, 1.0, true);
  cut.box.x1 = (cut.box.x0 + cut.box.x1) / 2;
  const auto out = MergeDetections({cut, Seen(25, 2, 0, 0, 1, 0.7f, 1.0, 1.0, 1.0)}, kNames, 256, frame);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].size_m[0], 1.0, 0.005);
  EXPECT_FALSE(out[0].truncated);
  EXPECT_FLOAT_EQ(out[0].score, 0.99f);
  const auto alone = MergeDetections({cut}, kNames, 256, frame);
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_TRUE(alone[0].truncated);
}

TEST(Merge, OverlappingClassesKeepTheHigherScoreAndRecordTheOther) {
  const LocalFrame frame(kOrigin);
  const auto out = MergeDetections({Seen(25, 0, 0, 0, 0, 0.6f, 0, 0, 1.0), Seen(25, 0, 0, 1, 1, 0.8f, 0.02, 0, 1.0)},
                                   kNames, 256, frame);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].class_name, "crate");
  EXPECT_EQ(out[0].alt_class, "tyre");
}

TEST(Merge, AnyInputOrderGivesTheSameResult) {
  const LocalFrame frame(kOrigin);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(-20, 20), size(0.3, 2.0), jitter(-0.03, 0.03);
  std::vector<RawDetection> raw;
  for (int obj = 0; obj < 30; ++obj) {
    const double e = pos(rng), n = pos(rng), s = size(rng);
    for (int k = 0; k < 3; ++k)
      raw.push_back(Seen(k == 2 ? 23 : 25, 2 * k, 0, obj, obj % 2, 0.5f + 0.01f * k, e + jitter(rng), n, s));
  }
  const auto ref = MergeDetections(raw, kNames, 256, frame);
  EXPECT_GE(ref.size(), 20u);
  for (int trial = 0; trial < 5; ++trial) {
    std::shuffle(raw.begin(), raw.end(), rng);
    const auto out = MergeDetections(raw, kNames, 256, frame);
    ASSERT_EQ(out.size(), ref.size());
    for (size_t i = 0; i < out.size(); ++i) {
      EXPECT_EQ(out[i].class_name, ref[i].class_name);
      EXPECT_EQ(out[i].position_m.east, ref[i].position_m.east);
      EXPECT_EQ(out[i].position_m.north, ref[i].position_m.north);
      EXPECT_EQ(out[i].levels, ref[i].levels);
      EXPECT_EQ(out[i].alt_class, ref[i].alt_class);
    }
  }
}

}  // namespace
}  // namespace seamap
