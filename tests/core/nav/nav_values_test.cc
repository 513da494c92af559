#include "core/nav/nav_values.h"

#include <gtest/gtest.h>

#include "core/nav/column_aliases.h"

namespace seamap {
namespace {

double Number(const std::string& text, bool decimal_comma = false) {
  std::string why;
  auto value = ParseNumber(text, &why, decimal_comma);
  EXPECT_TRUE(value) << text << ": " << why;
  return value.value_or(-999);
}

std::string Refusal(const std::string& text) {
  std::string why;
  EXPECT_FALSE(ParseNumber(text, &why)) << text;
  return why;
}

TEST(NavValues, ParsesPlainNumbers) {
  EXPECT_DOUBLE_EQ(Number(" 1.5 "), 1.5);
  EXPECT_DOUBLE_EQ(Number("+2"), 2);
  EXPECT_DOUBLE_EQ(Number("-3e2"), -300);
  EXPECT_DOUBLE_EQ(Number("1,25", true), 1.25);
}

TEST(NavValues, AcceptsNonAsciiMinusSigns) {
  EXPECT_DOUBLE_EQ(Number("\xE2\x88\x92"
                          "1.2"),
                   -1.2);  // U+2212 minus sign
  EXPECT_DOUBLE_EQ(Number("\xE2\x80\x93"
                          "4"),
                   -4);  // en dash
  EXPECT_DOUBLE_EQ(Number("\xEF\xBC\x8D"
                          "5"),
                   -5);  // full-width hyphen-minus
  EXPECT_DOUBLE_EQ(Number("1e\xE2\x88\x92"
                          "2"),
                   0.01);
}

TEST(NavValues, RefusesNanInfEmptyAndGarbage) {
  EXPECT_NE(Refusal("NaN").find("NaN"), std::string::npos);
  EXPECT_NE(Refusal("nan").find("NaN"), std::string::npos);
  EXPECT_NE(Refusal("inf").find("not finite"), std::string::npos);
  EXPECT_NE(Refusal("-Infinity").find("not finite"), std::string::npos);
  EXPECT_NE(Refusal("1e999").find("out of range"), std::string::npos);
  EXPECT_EQ(Refusal(""), "is empty");
  EXPECT_NE(Refusal("12abc").find("not a number: '12abc'"), std::string::npos);
  EXPECT_NE(Refusal("1,5").find("not a number"), std::string::npos);  // no decimal comma in ',' files
  Refusal("+");
  Refusal("+-1");
}

TEST(NavValues, ParsesTimes) {
  std::string why;
  EXPECT_DOUBLE_EQ(*ParseTimeSeconds("12.5", &why), 12.5);
  EXPECT_DOUBLE_EQ(*ParseTimeSeconds("01:02:03.5", &why), 3723.5);
  EXPECT_DOUBLE_EQ(*ParseTimeSeconds("1970-01-02T00:00:01Z", &why), 86401);
  EXPECT_DOUBLE_EQ(*ParseTimeSeconds("2023-05-01T12:00:00.25Z", &why), 1682942400.25);
  EXPECT_DOUBLE_EQ(*ParseTimeSeconds("2023-05-01 14:00:00+02:00", &why), 1682942400);
  EXPECT_FALSE(ParseTimeSeconds("2023-05-01T25:99", &why));
  EXPECT_NE(why.find("not a time"), std::string::npos);
  EXPECT_FALSE(ParseTimeSeconds("soon", &why));
}

TEST(NavValues, ParsesUtmZones) {
  std::string why;
  EXPECT_EQ(ParseUtmZone("52", &why)->zone, 52);
  EXPECT_FALSE(ParseUtmZone("52", &why)->north.has_value());
  EXPECT_TRUE(*ParseUtmZone("52N", &why)->north);
  EXPECT_FALSE(*ParseUtmZone("33 S", &why)->north);
  EXPECT_FALSE(*ParseUtmZone("33south", &why)->north);
  EXPECT_TRUE(*ParseUtmZone("52T", &why)->north);   // MGRS band
  EXPECT_FALSE(*ParseUtmZone("19H", &why)->north);  // MGRS band
  EXPECT_FALSE(ParseUtmZone("61", &why));
  EXPECT_FALSE(ParseUtmZone("0", &why));
  EXPECT_FALSE(ParseUtmZone("N", &why));
  EXPECT_FALSE(ParseUtmZone("52Q7", &why));
}

TEST(ColumnAliases, MapsEveryAlias) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> expected = {
      {"image", {"filename", "file", "image", "image_name", "photo", "frame"}},
      {"time_s", {"time", "t", "timestamp", "time_s", "seconds"}},
      {"x_m", {"x", "x_m", "east", "east_m", "easting_local"}},
      {"y_m", {"y", "y_m", "north", "north_m"}},
      {"lat", {"lat", "latitude", "lat_deg"}},
      {"lon", {"lon", "lng", "long", "longitude", "lon_deg"}},
      {"easting", {"easting"}},
      {"northing", {"northing"}},
      {"utm_zone", {"utm_zone", "zone"}},
      {"altitude_m", {"alt", "altitude", "altitude_m", "alt_m", "height"}},
      {"depth_m", {"depth", "depth_m"}},
      {"heading_deg", {"heading", "heading_deg", "yaw", "yaw_deg", "hdg"}},
      {"pitch_deg", {"pitch", "pitch_deg"}},
      {"roll_deg", {"roll", "roll_deg"}},
  };
  for (const auto& [canonical, aliases] : expected)
    for (const auto& alias : aliases) EXPECT_EQ(CanonicalColumn(alias), canonical) << alias;
  EXPECT_EQ(CanonicalColumn("  LATITUDE "), "lat");
  EXPECT_EQ(CanonicalColumn("Altitude (m)"), "altitude_m");
  EXPECT_EQ(CanonicalColumn("Heading [deg]"), "heading_deg");
  EXPECT_EQ(CanonicalColumn("Image Name"), "image");
  EXPECT_EQ(CanonicalColumn("temperature"), "");
}

}  // namespace
}  // namespace seamap
