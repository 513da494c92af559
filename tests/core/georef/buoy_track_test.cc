#include "core/georef/buoy_track.h"

#include <gtest/gtest.h>

#include <random>

namespace seamap {
namespace {

std::vector<BuoyFix> StraightTow(double sigma, int n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, 1);
  std::vector<BuoyFix> fixes;
  for (int j = 0; j < n; ++j)
    fixes.push_back({100.0 + j, {0.4 * j + sigma * noise(rng), 0.3 * j + sigma * noise(rng)}, 0, 0, j + 2});
  return fixes;
}

TEST(BuoyTrack, EstimatesTheGpsSigmaFromTheScatter) {
  const BuoyTrack track(StraightTow(1.5, 2000, 1));
  EXPECT_EQ(track.sigma_source(), "scatter");
  EXPECT_NEAR(track.sigma_m(), 1.5, 0.1);
  EXPECT_NEAR(track.fix_rate_hz(), 1.0, 1e-9);
}

TEST(BuoyTrack, MultipathJumpsDoNotInflateTheSigma) {
  auto fixes = StraightTow(1.0, 2000, 2);
  for (size_t j = 0; j < fixes.size(); j += 20) fixes[j].position_en_m.x() += 20;  // 5 % thrown 20 m
  EXPECT_NEAR(BuoyTrack(fixes).sigma_m(), 1.0, 0.15);
}

TEST(BuoyTrack, NoiseFreeFixesAreFlooredAtACentimetre) {
  EXPECT_DOUBLE_EQ(BuoyTrack(StraightTow(0, 50, 3)).sigma_m(), 0.01);
}

TEST(BuoyTrack, GivenSigmasAndHdopWin) {
  auto fixes = StraightTow(2.0, 500, 4);
  for (auto& f : fixes) f.hdop = 2.0;
  const BuoyTrack by_hdop(fixes);
  EXPECT_EQ(by_hdop.sigma_source(), "hdop");
  EXPECT_NEAR(by_hdop.sigma_m(), 2.0, 0.2);  // range error 1 m x hdop 2
  for (auto& f : fixes) f.sigma_m = 0.7;
  EXPECT_DOUBLE_EQ(BuoyTrack(fixes).sigma_m(), 0.7);
}

TEST(BuoyTrack, BracketedNeedsAFixCloseOnEachSide) {
  std::vector<BuoyFix> fixes = {{0, {0, 0}}, {1, {0, 1}}, {10, {0, 10}}};
  const BuoyTrack track(fixes);
  EXPECT_TRUE(track.Bracketed(0.5, 3));
  EXPECT_TRUE(track.Bracketed(1, 3));
  EXPECT_FALSE(track.Bracketed(5, 3));   // in the gap
  EXPECT_FALSE(track.Bracketed(-1, 3));  // before the first fix
  EXPECT_FALSE(track.Bracketed(11, 3));
}

TEST(BuoyTrack, LocalFitIsExactOnACleanLineAndDropsAJump) {
  auto fixes = StraightTow(0, 60, 5);
  fixes[30].position_en_m.y() += 20;
  const BuoyTrack track(fixes);
  const BuoyLocalFit fit = track.FitAt(131.5, 20, 0, 1e9);
  ASSERT_TRUE(fit.ok);
  EXPECT_EQ(fit.dropped, 1);
  EXPECT_NEAR(fit.position_en_m.x(), 0.4 * 31.5, 1e-9);
  EXPECT_NEAR(fit.position_en_m.y(), 0.3 * 31.5, 1e-9);
  EXPECT_NEAR(fit.velocity_en_mps.x(), 0.4, 1e-9);
  EXPECT_NEAR(fit.velocity_en_mps.y(), 0.3, 1e-9);
  EXPECT_FALSE(track.FitAt(100, 20, 0, 1e9).ok);  // nothing before the first fix
}

TEST(BuoyTrack, SpreadAndSpeed) {
  const BuoyTrack track(StraightTow(0, 101, 6));
  EXPECT_NEAR(track.MedianSpeed(100, 200), 0.5, 1e-9);
  EXPECT_NEAR(track.Spread(100, 200), 0.5 * std::sqrt((101.0 * 101 - 1) / 12), 1e-6);
}

}  // namespace
}  // namespace seamap
