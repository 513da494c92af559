// Real vehicle logs through the config's column map: a time split over
// columns (core/nav/split_time.h), angles in radians, and the warning when
// radians would be taken for degrees.
#include <gtest/gtest.h>

#include <cmath>

#include "core/nav/nav_reader.h"
#include "core/nav/split_time.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;
using ::seamap::testing::WriteFile;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

bool AnyContains(const std::vector<std::string>& texts, const std::string& part) {
  for (const auto& text : texts)
    if (Contains(text, part)) return true;
  return false;
}

// The ACFR AUV log's header and first two rows (shared/data/README.md).
const char* kAcfrHead =
    "year,month,day,hour,minute,second,northing,easting,depth,latitude,longitude,roll,pitch,heading,altitude,"
    "leftimage,rightimage\n"
    "2009,6,11,6,54,20.38,175.4130384,2.1557401,95.0943058,-42.1452543,148.4820782,0.0053453,0.0006529,-0.6283155,"
    "3.9200000,PR_20090611_065420_385_LC16.png,PR_20090611_065420_385_RM16.png\n"
    "2009,6,11,6,54,21.38,175.6424224,2.2052246,95.1445627,-42.1452523,148.4820788,0.0027041,0.0078674,-0.7600488,"
    "3.9300000,PR_20090611_065421_386_LC16.png,PR_20090611_065421_386_RM16.png\n";

NavReadOptions AcfrOptions() {
  NavReadOptions options;
  options.columns = {{"image", "leftimage"}};
  options.time_columns = {{"year", "year"}, {"month", "month"},   {"day", "day"},
                          {"hour", "hour"}, {"minute", "minute"}, {"second", "second"}};
  options.angle_unit = AngleUnit::kRadians;
  return options;
}

class NavColumnsTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& text) { return WriteFile(dir_ / "nav.csv", text).string(); }
  TempDir dir_;
};

TEST_F(NavColumnsTest, ReadsTheAcfrLogThroughTheColumnMap) {
  const std::string path = Write(kAcfrHead);
  try {
    ReadNavigation(path, {});  // no image or time column without the map
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_TRUE(Contains(e.what(), "navigation.time_columns")) << e.what();
  }
  const NavTable table = ReadNavigation(path, AcfrOptions());
  ASSERT_EQ(table.records.size(), 2u);
  EXPECT_TRUE(table.rejected.empty());
  EXPECT_TRUE(table.has_times);
  const NavRecord& a = table.records[0];
  EXPECT_EQ(a.image, "PR_20090611_065420_385_LC16.png");
  ASSERT_TRUE(a.time_s);
  EXPECT_NEAR(*a.time_s, 1244703260.38, 1e-5);  // 2009-06-11T06:54:20.38Z
  EXPECT_NEAR(*table.records[1].time_s - *a.time_s, 1.0, 1e-6);
  EXPECT_NEAR(a.pose.heading_deg, 360 - 0.6283155 * 180 / M_PI, 1e-9);
  EXPECT_NEAR(a.pose.roll_deg, 0.0053453 * 180 / M_PI, 1e-9);
  EXPECT_NEAR(a.pose.pitch_deg, 0.0006529 * 180 / M_PI, 1e-9);
  EXPECT_DOUBLE_EQ(a.pose.altitude_m, 3.92);
  EXPECT_DOUBLE_EQ(a.pose.depth_m, 95.0943058);
  EXPECT_DOUBLE_EQ(table.origin.lat, -42.1452543);
  EXPECT_DOUBLE_EQ(table.origin.lon, 148.4820782);
  // The time's columns are not "unknown"; the stereo pair's right image is.
  EXPECT_TRUE(AnyContains(table.warnings, "ignoring unknown columns: rightimage"));
  EXPECT_FALSE(AnyContains(table.warnings, "year"));
  EXPECT_FALSE(AnyContains(table.warnings, "radians"));
}

TEST_F(NavColumnsTest, RadiansAreNeverTakenForDegreesSilently) {
  const std::string path = Write(kAcfrHead);
  NavReadOptions options = AcfrOptions();
  options.angle_unit.reset();
  const NavTable unstated = ReadNavigation(path, options);
  ASSERT_EQ(unstated.records.size(), 2u);
  EXPECT_NEAR(unstated.records[0].pose.heading_deg, 360 - 0.6283155, 1e-9);  // as written, in degrees
  EXPECT_TRUE(AnyContains(unstated.warnings, "headings never leave +-pi"))
      << ::testing::PrintToString(unstated.warnings);
  EXPECT_TRUE(AnyContains(unstated.warnings, "\"angle_unit\": \"radians\""));

  options.angle_unit = AngleUnit::kDegrees;  // stated: no warning
  EXPECT_FALSE(AnyContains(ReadNavigation(path, options).warnings, "+-pi"));

  // Degrees stated as radians.
  const std::string degrees = Write("image,lat,lon,alt,heading\na.png,43,131,2,10\nb.png,43,131,2,200\n");
  options = {};
  EXPECT_FALSE(AnyContains(ReadNavigation(degrees, options).warnings, "pi"));
  options.angle_unit = AngleUnit::kRadians;
  EXPECT_TRUE(AnyContains(ReadNavigation(degrees, options).warnings, "beyond +-2 pi"));

  // Headings all 0 say nothing about their unit.
  const std::string zero = Write("image,lat,lon,alt,heading\na.png,43,131,2,0\nb.png,43,131,2,0\n");
  EXPECT_TRUE(ReadNavigation(zero, {}).warnings.empty());
}

TEST_F(NavColumnsTest, SplitDateAndTimeCrossMidnight) {
  NavReadOptions options;
  options.time_columns = {{"date", "Date"}, {"time", "UTC"}};
  const NavTable table = ReadNavigation(Write("image,Date,UTC,lat,lon,alt\n"
                                              "a.png,2009-06-11,23:59:59.5,43,131,2\n"
                                              "b.png,2009-06-12,00:00:00.5,43,131,2\n"
                                              "c.png,20090612,00:00:01.5,43,131,2\n"),
                                        options);
  ASSERT_EQ(table.records.size(), 3u);
  EXPECT_NEAR(*table.records[0].time_s, 1244764799.5, 1e-6);
  EXPECT_NEAR(*table.records[1].time_s - *table.records[0].time_s, 1.0, 1e-6);
  EXPECT_NEAR(*table.records[2].time_s - *table.records[1].time_s, 1.0, 1e-6);
  EXPECT_TRUE(table.warnings.empty()) << ::testing::PrintToString(table.warnings);

  // Parts in columns an alias would take for time_s: the parts win, another time column is ignored, said so.
  options.time_columns = {{"date", "date"}, {"time", "time"}};
  const NavTable aliased = ReadNavigation(Write("image,date,time,timestamp,lat,lon,alt\n"
                                                "a.png,2009-06-11,06:54:20.38,5,43,131,2\n"),
                                          options);
  ASSERT_EQ(aliased.records.size(), 1u);
  EXPECT_NEAR(*aliased.records[0].time_s, 1244703260.38, 1e-5);
  ASSERT_EQ(aliased.warnings.size(), 1u);
  EXPECT_TRUE(Contains(aliased.warnings[0], "ignoring column 'timestamp'")) << aliased.warnings[0];

  // Year, month, day, hour, minute, second over the end of a leap February.
  options.time_columns = {{"year", "y"}, {"month", "mo"},  {"day", "d"},
                          {"hour", "h"}, {"minute", "mi"}, {"second", "s"}};
  const NavTable parts = ReadNavigation(Write("image,y,mo,d,h,mi,s,lat,lon,alt\n"
                                              "a.png,2024,2,28,23,59,59,43,131,2\n"
                                              "b.png,2024,2,29,0,0,0,43,131,2\n"
                                              "c.png,2024,2,30,0,0,0,43,131,2\n"),
                                        options);
  ASSERT_EQ(parts.records.size(), 2u);
  EXPECT_NEAR(*parts.records[1].time_s, 1709164800, 1e-6);
  EXPECT_NEAR(*parts.records[1].time_s - *parts.records[0].time_s, 1.0, 1e-6);
  ASSERT_EQ(parts.rejected.size(), 1u);
  EXPECT_EQ(parts.rejected[0].line, 4);
  EXPECT_EQ(parts.rejected[0].field, "day");
  EXPECT_TRUE(Contains(parts.rejected[0].reason, "1..29, got 30")) << parts.rejected[0].reason;

  // A time of day without a date: carried into the next day, and said so.
  options.time_columns = {{"hour", "h"}, {"minute", "mi"}, {"second", "s"}};
  const NavTable clock = ReadNavigation(Write("image,h,mi,s,lat,lon,alt\n"
                                              "a.png,23,59,59.5,43,131,2\n"
                                              "b.png,0,0,0.5,43,131,2\n"),
                                        options);
  ASSERT_EQ(clock.records.size(), 2u);
  EXPECT_NEAR(*clock.records[1].time_s - *clock.records[0].time_s, 1.0, 1e-6);
  EXPECT_TRUE(AnyContains(clock.warnings, "nav.csv:3: the time of day passes midnight"))
      << ::testing::PrintToString(clock.warnings);
  EXPECT_FALSE(AnyContains(clock.warnings, "backwards"));
}

TEST_F(NavColumnsTest, BadTimePartsAreNamed) {
  NavReadOptions options = AcfrOptions();
  // Lines with a bad part are skipped, naming the part.
  std::string text = kAcfrHead;
  text += "2009,13,11,6,54,22.38,175.7,2.1,95.2,-42.1452512,148.4820784,0,0,-0.9,3.8,l.png,r.png\n";
  text += "2009,6,11,6,54,61.5,175.7,2.1,95.2,-42.1452512,148.4820784,0,0,-0.9,3.8,l.png,r.png\n";
  text += "2009,6,11,,54,22,175.7,2.1,95.2,-42.1452512,148.4820784,0,0,-0.9,3.8,l.png,r.png\n";
  text += "2009,6,11,6.5,54,22,175.7,2.1,95.2,-42.1452512,148.4820784,0,0,-0.9,3.8,l.png,r.png\n";
  const NavTable table = ReadNavigation(Write(text), options);
  EXPECT_EQ(table.records.size(), 2u);
  ASSERT_EQ(table.rejected.size(), 4u);
  EXPECT_EQ(table.rejected[0].field, "month");
  EXPECT_TRUE(Contains(table.rejected[0].reason, "1..12, got 13")) << table.rejected[0].reason;
  EXPECT_EQ(table.rejected[1].field, "second");
  EXPECT_EQ(table.rejected[2].field, "hour");
  EXPECT_TRUE(Contains(table.rejected[2].reason, "empty")) << table.rejected[2].reason;
  EXPECT_EQ(table.rejected[3].field, "hour");
  EXPECT_TRUE(Contains(table.rejected[3].reason, "whole number")) << table.rejected[3].reason;

  // A part's column missing from the header is fatal, naming the config key.
  options.time_columns["hour"] = "HH";
  try {
    ReadNavigation(Write(kAcfrHead), options);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "navigation.time_columns.hour");
    EXPECT_TRUE(Contains(e.what(), "'HH'")) << e.what();
  }
}

TEST(NavReadOptionsCheck, NamesTheTimeColumnsKey) {
  auto problem = [](std::map<std::string, std::string> parts) {
    NavReadOptions options;
    options.time_columns = std::move(parts);
    try {
      options.Check("c.json");
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "navigation.time_columns");
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(problem({{"date", "d"}, {"time", "t"}}), "");
  EXPECT_EQ(problem({{"time", "t"}}), "");
  EXPECT_TRUE(Contains(problem({{"year", "y"}, {"time", "t"}}), "year', 'month', 'day'"));
  EXPECT_TRUE(Contains(problem({{"date", "d"}}), "a time needs"));
  EXPECT_TRUE(Contains(problem({{"hour", "h"}, {"minute", "m"}}), "a time needs"));
  EXPECT_TRUE(Contains(problem({{"time", "t"}, {"hour", "h"}}), "not both"));
  EXPECT_TRUE(Contains(problem({{"time", "t"}, {"week", "w"}}), "unknown part 'week'"));
  EXPECT_TRUE(Contains(problem({{"time", " "}}), "names no column"));

  NavReadOptions doubled;
  doubled.time_columns = {{"time", "t"}};
  doubled.columns = {{"time_s", "t"}};
  EXPECT_THROW(doubled.Check("c.json"), InputError);
}

}  // namespace
}  // namespace seamap
