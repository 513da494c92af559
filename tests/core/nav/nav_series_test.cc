#include "core/nav/nav_series.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace seamap {
namespace {

NavRecord At(double t, double east, double heading) {
  NavRecord r;
  r.time_s = t;
  r.pose.east_m = east;
  r.pose.north_m = -east;
  r.pose.altitude_m = 2 + east;
  r.pose.depth_m = 10 * east;
  r.pose.pitch_deg = east;
  r.pose.roll_deg = -east;
  r.pose.heading_deg = heading;
  return r;
}

TEST(NavSeries, LinearInsideTheSpanEmptyOutside) {
  const NavSeries series({At(0, 0, 0), At(10, 10, 90), At(20, 30, 90)});
  auto mid = series.PoseAt(5);
  ASSERT_TRUE(mid);
  EXPECT_DOUBLE_EQ(mid->east_m, 5);
  EXPECT_DOUBLE_EQ(mid->north_m, -5);
  EXPECT_DOUBLE_EQ(mid->altitude_m, 7);
  EXPECT_DOUBLE_EQ(mid->depth_m, 50);
  EXPECT_DOUBLE_EQ(mid->pitch_deg, 5);
  EXPECT_DOUBLE_EQ(mid->roll_deg, -5);
  EXPECT_DOUBLE_EQ(mid->heading_deg, 45);
  EXPECT_DOUBLE_EQ(series.PoseAt(15)->east_m, 20);
  EXPECT_DOUBLE_EQ(series.PoseAt(0)->east_m, 0);
  EXPECT_DOUBLE_EQ(series.PoseAt(10)->east_m, 10);
  EXPECT_DOUBLE_EQ(series.PoseAt(20)->east_m, 30);
  EXPECT_FALSE(series.PoseAt(-0.1));
  EXPECT_FALSE(series.PoseAt(20.1));
  EXPECT_FALSE(NavSeries({}).PoseAt(0));
}

TEST(NavSeries, HeadingTakesTheShortArc) {
  EXPECT_NEAR(NavSeries({At(0, 0, 350), At(2, 0, 10)}).PoseAt(1)->heading_deg, 0, 1e-9);
  EXPECT_NEAR(NavSeries({At(0, 0, 350), At(2, 0, 10)}).PoseAt(0.5)->heading_deg, 355, 1e-9);
  EXPECT_NEAR(NavSeries({At(0, 0, 10), At(2, 0, 350)}).PoseAt(1.5)->heading_deg, 355, 1e-9);
  EXPECT_NEAR(NavSeries({At(0, 0, 170), At(2, 0, 200)}).PoseAt(1)->heading_deg, 185, 1e-9);
}

TEST(NavSeries, UnsortedRecordsAreSortedAndUntimedOnesLeftOut) {
  NavRecord untimed = At(0, 99, 0);
  untimed.time_s.reset();
  const NavSeries shuffled({At(20, 30, 90), untimed, At(0, 0, 0), At(10, 10, 90)});
  const NavSeries sorted({At(0, 0, 0), At(10, 10, 90), At(20, 30, 90)});
  ASSERT_EQ(shuffled.records().size(), 3u);
  EXPECT_EQ(shuffled.first_time_s(), 0);
  EXPECT_EQ(shuffled.last_time_s(), 20);
  for (double t : {0.0, 2.5, 10.0, 17.0, 20.0}) {
    EXPECT_EQ(shuffled.PoseAt(t)->east_m, sorted.PoseAt(t)->east_m) << t;
    EXPECT_EQ(shuffled.PoseAt(t)->heading_deg, sorted.PoseAt(t)->heading_deg) << t;
  }
}

TEST(NavSeries, AtASharedTimeTheLastRecordInFileOrderCounts) {
  const NavSeries series({At(0, 0, 0), At(10, 10, 0), At(10, 12, 0), At(20, 22, 0)});
  EXPECT_EQ(series.PoseAt(10)->east_m, 12);
  EXPECT_DOUBLE_EQ(series.PoseAt(15)->east_m, 17);  // from the last record at 10
  EXPECT_DOUBLE_EQ(series.PoseAt(5)->east_m, 5);    // towards the first record at 10
  const NavSeries ends_twice({At(0, 0, 0), At(10, 10, 0), At(10, 12, 0)});
  EXPECT_EQ(ends_twice.PoseAt(10)->east_m, 12);
}

TEST(NavSeries, NonFiniteTimesAndEmptySeriesGiveNothing) {
  const NavSeries series({At(0, 0, 0), At(10, 10, 0)});
  EXPECT_FALSE(series.PoseAt(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(series.PoseAt(std::numeric_limits<double>::infinity()));
  EXPECT_EQ(series.SpanText(), "[0, 10] s");
  EXPECT_TRUE(NavSeries({}).empty());
  EXPECT_EQ(NavSeries({}).SpanText(), "(no timed records)");
}

}  // namespace
}  // namespace seamap
