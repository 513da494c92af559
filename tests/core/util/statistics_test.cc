#include "core/util/statistics.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace seamap {
namespace {

TEST(Median, OddCountIsTheMiddleValue) {
  EXPECT_EQ(Median({5, 1, 3}), 3);
  EXPECT_EQ(Median({7}), 7);
}

TEST(Median, EvenCountIsTheUpperOfTheMiddlePair) {
  EXPECT_EQ(Median({4, 1, 3, 2}), 3);
  EXPECT_EQ(Median({2, 1}), 2);
}

TEST(Median, EmptyIsZero) {
  EXPECT_EQ(Median({}), 0);
}

TEST(Percentile, InterpolatesBetweenOrderStatistics) {
  const std::vector<double> v = {40, 10, 30, 20};  // sorted 10 20 30 40, ranks 0..3
  EXPECT_EQ(Percentile(v, 0), 10);
  EXPECT_EQ(Percentile(v, 1), 40);
  EXPECT_DOUBLE_EQ(Percentile(v, 0.5), 25);  // rank 1.5
  EXPECT_DOUBLE_EQ(Percentile(v, 0.9), 37);  // rank 2.7
  EXPECT_EQ(Percentile(v, 2), 40);           // clamped
  EXPECT_EQ(Percentile(v, -1), 10);
}

TEST(Percentile, HalfIsExactlyTheMeanOfTheMiddlePair) {
  const double a = 0.1, b = 0.7;
  EXPECT_EQ(Percentile({b, a}, 0.5), 0.5 * (a + b));
  EXPECT_EQ(Percentile({3, 1, 2}, 0.5), 2);
}

TEST(Percentile, AnExactRankIgnoresItsNeighbour) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(Percentile({1, 2, inf}, 0.5), 2);
}

TEST(Percentile, EmptyIsZero) {
  EXPECT_EQ(Percentile({}, 0.5), 0);
}

}  // namespace
}  // namespace seamap
