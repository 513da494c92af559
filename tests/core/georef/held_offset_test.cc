#include "core/georef/held_offset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace seamap {
namespace {

TEST(HeldOffset, NothingWhereTheOperatorKnowsReachAndClock) {
  EXPECT_EQ(HeldOffset(2.0, 1.0, {0.0, 0.5}).mean_square_m2, 0);
  EXPECT_EQ(HeldOffset(2.0, 1.0, {1.0, 1.0}).mean_square_m2, 0);  // the default is certainly exact
}

TEST(HeldOffset, UnseenOffsetIsThePriors) {
  // Fixes that see nothing (standard error 100 m): the slab's share of its variance.
  EXPECT_NEAR(HeldOffset(3.0, 100.0, {1.0, 0.5}).mean_square_m2, 0.5, 0.01);
  EXPECT_NEAR(HeldOffset(-50.0, 100.0, {1.0, 0.0}).mean_square_m2, 1.0, 0.01);
}

TEST(HeldOffset, SeenOffsetIsTheDatas) {
  // Seen to 5 cm and none there: nearly nothing; 1 m there: about 1 m^2.
  EXPECT_LT(HeldOffset(0.02, 0.05, {1.0, 0.5}).mean_square_m2, 0.002);
  EXPECT_NEAR(HeldOffset(1.0, 0.05, {1.0, 0.5}).mean_square_m2, 1.0, 0.01);
  EXPECT_TRUE(std::isfinite(HeldOffset(40.0, 0.01, {1.0, 0.5}).mean_square_m2));  // far in the tail
  EXPECT_NEAR(HeldOffset(40.0, 0.01, {1.0, 0.5}).mean_square_m2, 1600.0, 1.0);
}

TEST(HeldOffset, CalibratedWhenThePriorIsTheWorlds) {
  // Offsets drawn from the prior itself, estimated with noise: the mean of
  // the predicted squares is the mean of the true squares (law of total
  // expectation), and the variance about the posterior mean is the mean
  // squared error of holding the offset there, at every standard error.
  // Holding there does better than at the default or at the estimate.
  const HeldOffsetPrior prior{0.8, 0.5};
  for (double sigma : {0.05, 0.3, 1.0, 3.0}) {
    std::mt19937 rng(7);
    std::normal_distribution<double> unit(0, 1);
    std::uniform_real_distribution<double> coin(0, 1);
    double truth_sq = 0, predicted_sq = 0, held_sq = 0, predicted_var = 0, estimate_sq = 0;
    const int n = 40000;
    for (int i = 0; i < n; ++i) {
      const double offset = coin(rng) < prior.exact_share ? 0 : prior.sigma_m * unit(rng);
      const double estimate = offset + sigma * unit(rng);
      const HeldOffsetPosterior p = HeldOffset(estimate, sigma, prior);
      truth_sq += offset * offset;
      predicted_sq += p.mean_square_m2;
      held_sq += (offset - p.mean_m) * (offset - p.mean_m);
      predicted_var += p.Variance();
      estimate_sq += (offset - estimate) * (offset - estimate);
    }
    EXPECT_NEAR(predicted_sq / truth_sq, 1.0, 0.04) << "sigma " << sigma;
    EXPECT_NEAR(predicted_var / held_sq, 1.0, 0.04) << "sigma " << sigma;
    EXPECT_LT(held_sq, truth_sq) << "sigma " << sigma;
    EXPECT_LT(held_sq, estimate_sq) << "sigma " << sigma;
  }
}

}  // namespace
}  // namespace seamap
