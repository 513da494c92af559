#include "core/georef/held_offset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace seamap {
namespace {

TEST(HeldOffsetMeanSquare, NothingWhereTheOperatorKnowsReachAndClock) {
  EXPECT_EQ(HeldOffsetMeanSquare(2.0, 1.0, {0.0, 0.5}), 0);
  EXPECT_EQ(HeldOffsetMeanSquare(2.0, 1.0, {1.0, 1.0}), 0);  // the default is certainly exact
}

TEST(HeldOffsetMeanSquare, UnseenOffsetIsThePriors) {
  // Fixes that see nothing (standard error 100 m): the slab's share of its variance.
  EXPECT_NEAR(HeldOffsetMeanSquare(3.0, 100.0, {1.0, 0.5}), 0.5, 0.01);
  EXPECT_NEAR(HeldOffsetMeanSquare(-50.0, 100.0, {1.0, 0.0}), 1.0, 0.01);
}

TEST(HeldOffsetMeanSquare, SeenOffsetIsTheDatas) {
  // Seen to 5 cm and none there: nearly nothing; 1 m there: about 1 m^2.
  EXPECT_LT(HeldOffsetMeanSquare(0.02, 0.05, {1.0, 0.5}), 0.002);
  EXPECT_NEAR(HeldOffsetMeanSquare(1.0, 0.05, {1.0, 0.5}), 1.0, 0.01);
  EXPECT_TRUE(std::isfinite(HeldOffsetMeanSquare(40.0, 0.01, {1.0, 0.5})));  // far in the tail
  EXPECT_NEAR(HeldOffsetMeanSquare(40.0, 0.01, {1.0, 0.5}), 1600.0, 1.0);
}

TEST(HeldOffsetMeanSquare, CalibratedWhenThePriorIsTheWorlds) {
  // Offsets drawn from the prior itself, estimated with noise: the mean of
  // the predicted squares is the mean of the true squares (law of total
  // expectation), at every standard error, seen or not.
  const HeldOffsetPrior prior{0.8, 0.5};
  for (double sigma : {0.05, 0.3, 1.0, 3.0}) {
    std::mt19937 rng(7);
    std::normal_distribution<double> unit(0, 1);
    std::uniform_real_distribution<double> coin(0, 1);
    double truth_sq = 0, predicted_sq = 0;
    const int n = 40000;
    for (int i = 0; i < n; ++i) {
      const double offset = coin(rng) < prior.exact_share ? 0 : prior.sigma_m * unit(rng);
      truth_sq += offset * offset;
      predicted_sq += HeldOffsetMeanSquare(offset + sigma * unit(rng), sigma, prior);
    }
    EXPECT_NEAR(predicted_sq / truth_sq, 1.0, 0.04) << "sigma " << sigma;
  }
}

}  // namespace
}  // namespace seamap
