#include "core/nav/nav_reader.h"

#include <gtest/gtest.h>

#include "core/geo/local_frame.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;
using ::seamap::testing::WriteFile;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class NavReaderTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& text, const std::string& name = "nav.csv") {
    return WriteFile(dir_ / name, text).string();
  }
  NavTable Read(const std::string& text, const NavReadOptions& options = {}) {
    return ReadNavigation(Write(text), options);
  }
  // The InputError the text causes; fails the test when there is none.
  InputError Fatal(const std::string& text, const NavReadOptions& options = {}) {
    const std::string path = Write(text);
    try {
      ReadNavigation(path, options);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      return e;
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return InputError("", 0, "", "");
  }
  // The rejection of a line, or a failure when the line was accepted.
  static Rejection RejectionAt(const NavTable& table, int line) {
    for (const auto& r : table.rejected)
      if (r.line == line) return r;
    ADD_FAILURE() << "line " << line << " was not rejected";
    return {};
  }
  static NavReadOptions WithOrigin(double lat, double lon) {
    NavReadOptions options;
    options.origin = LatLon{lat, lon};
    return options;
  }

  TempDir dir_;
};

TEST_F(NavReaderTest, ReadsAliasesWithEverySeparator) {
  for (const std::string sep : {",", ";", "\t", "  "}) {
    const std::string text = "FileName" + sep + "Latitude" + sep + "LONGITUDE" + sep + "Altitude" + sep + "Yaw" + sep +
                             "Pitch_deg" + sep + "roll" + sep + "Depth" + sep + "Timestamp\n" + "a.jpg" + sep + "43.1" +
                             sep + "131.9" + sep + "1.6" + sep + "30" + sep + "2" + sep + "-3" + sep + "25" + sep +
                             "100\n" + "b.jpg" + sep + "43.1001" + sep + "131.9" + sep + "1.8" + sep + "40" + sep +
                             "0" + sep + "0" + sep + "25.5" + sep + "100.2\n";
    const NavTable table = Read(text);
    ASSERT_EQ(table.records.size(), 2u) << "separator '" << sep << "'";
    EXPECT_TRUE(table.rejected.empty());
    EXPECT_TRUE(table.has_images);
    EXPECT_TRUE(table.has_times);
    EXPECT_TRUE(table.warnings.empty());
    const NavRecord& a = table.records[0];
    EXPECT_EQ(a.image, "a.jpg");
    EXPECT_EQ(a.line, 2);
    EXPECT_DOUBLE_EQ(*a.time_s, 100);
    EXPECT_DOUBLE_EQ(a.pose.altitude_m, 1.6);
    EXPECT_DOUBLE_EQ(a.pose.heading_deg, 30);
    EXPECT_DOUBLE_EQ(a.pose.pitch_deg, 2);
    EXPECT_DOUBLE_EQ(a.pose.roll_deg, -3);
    EXPECT_DOUBLE_EQ(a.pose.depth_m, 25);
    EXPECT_NEAR(table.records[1].pose.north_m, 11.1, 0.1);  // 0.0001 deg of latitude
  }
}

TEST_F(NavReaderTest, ReadsSemicolonFilesWithDecimalCommasAndQuotes) {
  const NavTable table = Read(
      "\xEF\xBB\xBFimage;x_m;y_m;alt\r\n\"my photo, 1.jpg\";1,5;\xE2\x88\x92"
      "2,25;1,75\r\n",
      WithOrigin(43.1, 131.9));
  ASSERT_EQ(table.records.size(), 1u);
  EXPECT_EQ(table.records[0].image, "my photo, 1.jpg");
  EXPECT_DOUBLE_EQ(table.records[0].pose.east_m, 1.5);
  EXPECT_DOUBLE_EQ(table.records[0].pose.north_m, -2.25);
  EXPECT_DOUBLE_EQ(table.records[0].pose.altitude_m, 1.75);
  EXPECT_FALSE(table.has_times);
}

TEST_F(NavReaderTest, LatLonBecomeLocalMetresFromTheFirstRecord) {
  const NavTable table = Read("image,lat,lon,alt\n# comment\na.jpg,43.1,131.9,2\nb.jpg,43.1005,131.9012,2\n");
  ASSERT_EQ(table.records.size(), 2u);
  EXPECT_DOUBLE_EQ(table.origin.lat, 43.1);
  EXPECT_DOUBLE_EQ(table.origin.lon, 131.9);
  EXPECT_NEAR(table.records[0].pose.east_m, 0, 1e-9);
  EXPECT_NEAR(table.records[0].pose.north_m, 0, 1e-9);
  const LocalXY expected = LocalFrame({43.1, 131.9}).FromLatLon({43.1005, 131.9012});
  EXPECT_NEAR(table.records[1].pose.east_m, expected.east, 1e-6);
  EXPECT_NEAR(table.records[1].pose.north_m, expected.north, 1e-6);
  // Rough independent check: 0.0012 deg of longitude at 43.1 N is about 97.6 m.
  EXPECT_NEAR(expected.east, 97.6, 0.3);
  EXPECT_NEAR(expected.north, 55.5, 0.3);
}

TEST_F(NavReaderTest, LatLonUseTheGivenOrigin) {
  const NavTable table = Read("image,lat,lon,alt\na.jpg,43.1,131.9,2\n", WithOrigin(43.0, 131.9));
  EXPECT_DOUBLE_EQ(table.origin.lat, 43.0);
  EXPECT_NEAR(table.records[0].pose.north_m, 11105, 15);  // 0.1 deg of latitude
  EXPECT_NEAR(table.records[0].pose.east_m, 0, 1e-6);
}

TEST_F(NavReaderTest, LocalPositionsNeedAnOrigin) {
  const InputError e = Fatal("\n\nimage,x_m,y_m,alt\na.jpg,1,2,1.5\n");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.field(), "x_m");
  EXPECT_TRUE(Contains(e.what(), "--origin")) << e.what();

  const NavTable table = Read("image,east,north,height\na.jpg,1,2,1.5\n", WithOrigin(43.1, 131.9));
  EXPECT_DOUBLE_EQ(table.records[0].pose.east_m, 1);
  EXPECT_DOUBLE_EQ(table.records[0].pose.north_m, 2);
  EXPECT_DOUBLE_EQ(table.origin.lat, 43.1);
}

TEST_F(NavReaderTest, UtmWithZoneColumn) {
  // Reference from PROJ's cs2cs: UTM 52N (500000, 4000000) = 36.144718099 N, 129 E.
  const NavTable table = Read(
      "image,easting,northing,zone,alt\n"
      "a.jpg,500000,4000000,52N,2\n"
      "b.jpg,500100,4000000,52N,2\n");
  ASSERT_EQ(table.records.size(), 2u) << table.rejected.front().Message();
  EXPECT_NEAR(table.origin.lat, 36.144718099, 1e-8);
  EXPECT_NEAR(table.origin.lon, 129.0, 1e-8);
  // 100 m of UTM easting on the central meridian is 100 / 0.9996 m on the ground.
  EXPECT_NEAR(table.records[1].pose.east_m, 100 / 0.9996, 1e-3);
  EXPECT_NEAR(table.records[1].pose.north_m, 0, 1e-3);
}

TEST_F(NavReaderTest, UtmWithZoneOptionInTheSouth) {
  NavReadOptions options;
  options.utm_zone = 33;
  options.utm_north = false;
  // cs2cs: UTM 33S (300000, 6000000) = 36.124095832 S, 12.777608615 E.
  const NavTable table = Read("image,utm_easting,utm_northing,alt\na.jpg,300000,6000000,2\n", options);
  EXPECT_NEAR(table.origin.lat, -36.124095832, 1e-8);
  EXPECT_NEAR(table.origin.lon, 12.777608615, 1e-8);
}

TEST_F(NavReaderTest, UtmWithoutZoneIsFatal) {
  const InputError e = Fatal("image,easting,northing,alt\na.jpg,500000,4000000,2\n");
  EXPECT_EQ(e.field(), "utm_zone");
  EXPECT_EQ(e.line(), 1);
}

TEST_F(NavReaderTest, UtmBadZoneRejectsTheLine) {
  const NavTable table =
      Read("image,easting,northing,zone,alt\na.jpg,500000,4000000,52N,2\nb.jpg,500000,4000000,75,2\n");
  ASSERT_EQ(table.records.size(), 1u);
  const Rejection r = RejectionAt(table, 3);
  EXPECT_EQ(r.field, "utm_zone");
  EXPECT_TRUE(Contains(r.Message(), "nav.csv:3: utm_zone")) << r.Message();
}

TEST_F(NavReaderTest, ReadsTheSeedTextFormat) {
  const NavTable table = Read(
      "09204051.jpg X(m): 1.0, Y(m): 2.0, Alt(m): 1.6, Heading(deg): 30.0,\n"
      "\n"
      "09204052.jpg X (m): \xE2\x88\x92"
      "1.5, Y (m): 2.5, Alt (m): 1.7, Heading (deg): -10, Pitch(deg): 3, Roll(deg): -4, Depth(m): 20, Time(s): 7.5, "
      "Temp(C): 4,\n"
      "09204053.jpg X(m): 1.0, Y(m): 2.0, Heading(deg): 30.0,\n",
      WithOrigin(43.1, 131.9));
  ASSERT_EQ(table.records.size(), 2u);
  EXPECT_TRUE(table.has_images);
  EXPECT_TRUE(table.has_times);
  const NavRecord& a = table.records[0];
  EXPECT_EQ(a.image, "09204051.jpg");
  EXPECT_DOUBLE_EQ(a.pose.east_m, 1.0);
  EXPECT_DOUBLE_EQ(a.pose.north_m, 2.0);
  EXPECT_DOUBLE_EQ(a.pose.altitude_m, 1.6);
  EXPECT_DOUBLE_EQ(a.pose.heading_deg, 30.0);
  const NavRecord& b = table.records[1];
  EXPECT_EQ(b.line, 3);
  EXPECT_DOUBLE_EQ(b.pose.east_m, -1.5);
  EXPECT_DOUBLE_EQ(b.pose.heading_deg, 350);
  EXPECT_DOUBLE_EQ(b.pose.pitch_deg, 3);
  EXPECT_DOUBLE_EQ(b.pose.roll_deg, -4);
  EXPECT_DOUBLE_EQ(b.pose.depth_m, 20);
  EXPECT_DOUBLE_EQ(*b.time_s, 7.5);
  const Rejection r = RejectionAt(table, 4);
  EXPECT_EQ(r.field, "altitude_m");
  EXPECT_TRUE(Contains(r.reason, "missing")) << r.reason;
  ASSERT_EQ(table.warnings.size(), 1u);
  EXPECT_TRUE(Contains(table.warnings[0], "Temp(C)")) << table.warnings[0];

  const InputError e = Fatal("a.jpg X(m): 1.0, Y(m): 2.0, Alt(m): 1.6,\n");
  EXPECT_EQ(e.field(), "x_m");
}

TEST_F(NavReaderTest, BadValuesRejectTheLineNamingFileLineAndField) {
  const std::string path = Write(
      "image,lat,lon,alt,heading,pitch,roll\n"  // 1
      "a.jpg,43.1,131.9,1.6,30,0,0\n"           // 2 good
      "b.jpg,NaN,131.9,1.6,30,0,0\n"            // 3
      "c.jpg,95,131.9,1.6,30,0,0\n"             // 4
      "d.jpg,43.1,131.9,-1.2,30,0,0\n"          // 5
      "e.jpg,43.1,131.9,0,30,0,0\n"             // 6
      "f.jpg,43.1,131.9,1.6,inf,0,0\n"          // 7
      "g.jpg,43.1,131.9\n"                      // 8
      "h.jpg,43.1,131.9,1.6,\xE2\x88\x92"
      "30,0,0\n"                          // 9 good: Unicode minus
      "i.jpg,43.1,131.9,1.6,30,95,0\n"    // 10
      "j.jpg,43.1,131.9,1.6,,0,0\n"       // 11
      "k.jpg,43.1,131.9,abc,30,0,0\n"     // 12
      "l.jpg,43.1,-181,1.6,30,0,0\n"      // 13
      "m.jpg,43.1,131.9,1.6,30,0,0,7\n"   // 14 too many fields
      "n.jpg,43.1,131.9,1.6,30,0,0,\n");  // 15 good: trailing separator
  const NavTable table = ReadNavigation(path, {});
  ASSERT_EQ(table.records.size(), 3u);
  EXPECT_EQ(table.records[1].image, "h.jpg");
  EXPECT_DOUBLE_EQ(table.records[1].pose.heading_deg, 330);
  EXPECT_EQ(table.rejected.size(), 11u);

  struct Case {
    int line;
    std::string field, words;
  };
  for (const Case& c : std::vector<Case>{{3, "lat", "lat is not a number (NaN)"},
                                         {4, "lat", "lat must be within [-90, 90], got 95"},
                                         {5, "altitude_m", "altitude_m must be > 0, got -1.2"},
                                         {6, "altitude_m", "altitude_m must be > 0, got 0"},
                                         {7, "heading_deg", "heading_deg is not finite"},
                                         {8, "altitude_m", "missing column 'alt'"},
                                         {10, "pitch_deg", "pitch_deg must be within (-90, 90), got 95"},
                                         {11, "heading_deg", "heading_deg is empty"},
                                         {12, "altitude_m", "altitude_m is not a number: 'abc'"},
                                         {13, "lon", "lon must be within [-180, 180], got -181"},
                                         {14, "", "8 fields but the header has 7"}}) {
    const Rejection r = RejectionAt(table, c.line);
    EXPECT_EQ(r.file, path);
    EXPECT_EQ(r.field, c.field) << "line " << c.line;
    const std::string message = r.Message();
    EXPECT_TRUE(Contains(message, path + ":" + std::to_string(c.line) + ": ")) << message;
    EXPECT_TRUE(Contains(message, c.field)) << message;
    EXPECT_TRUE(Contains(message, c.words)) << message;
  }
  // In file order.
  for (size_t i = 1; i < table.rejected.size(); ++i) EXPECT_LT(table.rejected[i - 1].line, table.rejected[i].line);
}

TEST_F(NavReaderTest, UnknownColumnsAreReportedOnce) {
  const std::string path = Write("image,lat,lon,alt,foo,Bar\na.jpg,43.1,131.9,2,1,2\nb.jpg,43.1,131.9,2,1,2\n");
  const NavTable table = ReadNavigation(path, {});
  EXPECT_EQ(table.records.size(), 2u);
  ASSERT_EQ(table.warnings.size(), 1u);
  EXPECT_EQ(table.warnings[0], path + ":1: ignoring unknown columns: foo, Bar");
}

TEST_F(NavReaderTest, EmptyAndMissingFilesAreFatal) {
  const InputError empty = Fatal("");
  EXPECT_TRUE(Contains(empty.what(), "empty")) << empty.what();
  const InputError header_only = Fatal("image,lat,lon,alt\n\n");
  EXPECT_TRUE(Contains(header_only.what(), "no navigation records")) << header_only.what();

  const std::string missing = (dir_ / "missing.csv").string();
  try {
    ReadNavigation(missing, {});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), missing);
    EXPECT_TRUE(Contains(e.what(), missing)) << e.what();
  }
}

TEST_F(NavReaderTest, HeaderWithoutPositionColumnsIsFatal) {
  const InputError e = Fatal("# log\nimage,alt,depth\na.jpg,2,30\n");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.field(), "position");
  EXPECT_TRUE(Contains(e.what(), "found: image, alt, depth")) << e.what();
  EXPECT_TRUE(Contains(e.what(), "latitude")) << e.what();

  const InputError half = Fatal("image,lat,alt\na.jpg,43,2\n");
  EXPECT_EQ(half.field(), "lon");
  EXPECT_TRUE(Contains(half.what(), "longitude")) << half.what();
}

TEST_F(NavReaderTest, HeaderWithoutAltitudeOrImageOrTimeIsFatal) {
  const InputError no_alt = Fatal("image,lat,lon\na.jpg,43,131\n");
  EXPECT_EQ(no_alt.field(), "altitude_m");
  EXPECT_TRUE(Contains(no_alt.what(), "found: image, lat, lon")) << no_alt.what();
  EXPECT_TRUE(Contains(no_alt.what(), "altitude")) << no_alt.what();
  const InputError no_image = Fatal("lat,lon,alt\n43,131,2\n");
  EXPECT_EQ(no_image.field(), "image");
}

TEST_F(NavReaderTest, NoValidRecordIsFatalAndNamesTheFirstProblem) {
  const InputError e = Fatal("image,lat,lon,alt\na.jpg,43,131,-1\nb.jpg,43,131,nan\n");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.field(), "altitude_m");
  EXPECT_TRUE(Contains(e.what(), "altitude_m must be > 0, got -1")) << e.what();
  EXPECT_TRUE(Contains(e.what(), "2 lines rejected")) << e.what();
}

TEST_F(NavReaderTest, ExtraColumnNamesFromOptions) {
  NavReadOptions options;
  options.columns = {{"altitude_m", "Dist To Bottom"}, {"image", "shot"}};
  const NavTable table = Read("shot,lat,lon,dist to bottom,alt\na.jpg,43,131,2.5,9\n", options);
  ASSERT_EQ(table.records.size(), 1u);
  EXPECT_EQ(table.records[0].image, "a.jpg");
  EXPECT_DOUBLE_EQ(table.records[0].pose.altitude_m, 2.5);
  ASSERT_EQ(table.warnings.size(), 1u);  // 'alt' repeats altitude_m
  EXPECT_TRUE(Contains(table.warnings[0], "alt")) << table.warnings[0];

  options.columns = {{"altitude", "dist"}};
  EXPECT_EQ(Fatal("shot,lat,lon,dist\na.jpg,43,131,2.5\n", options).field(), "altitude");
  options.columns = {{"altitude_m", "range"}};
  const InputError absent = Fatal("image,lat,lon,dist\na.jpg,43,131,2.5\n", options);
  EXPECT_EQ(absent.field(), "altitude_m");
  EXPECT_TRUE(Contains(absent.what(), "'range'")) << absent.what();
}

TEST_F(NavReaderTest, HeadingIsNormalised) {
  const NavTable table =
      Read("image,x,y,alt,hdg\na,0,0,1,-90\nb,0,0,1,720\nc,0,0,1,360\nd,0,0,1,359.5\n", WithOrigin(0, 0));
  ASSERT_EQ(table.records.size(), 4u);
  EXPECT_DOUBLE_EQ(table.records[0].pose.heading_deg, 270);
  EXPECT_DOUBLE_EQ(table.records[1].pose.heading_deg, 0);
  EXPECT_DOUBLE_EQ(table.records[2].pose.heading_deg, 0);
  EXPECT_DOUBLE_EQ(table.records[3].pose.heading_deg, 359.5);
}

TEST_F(NavReaderTest, TimeSeriesWithoutImagesAndBackwardTime) {
  const std::string path = Write("time,lat,lon,alt\n10,43,131,2\n11,43,131,2\n9,43,131,2\n12,43,131,2\n");
  const NavTable table = ReadNavigation(path, {});
  ASSERT_EQ(table.records.size(), 4u);
  EXPECT_FALSE(table.has_images);
  EXPECT_TRUE(table.has_times);
  EXPECT_EQ(table.records[2].line, 4);  // file order kept
  ASSERT_EQ(table.warnings.size(), 1u);
  EXPECT_TRUE(Contains(table.warnings[0], path + ":4: time goes backwards")) << table.warnings[0];
}

TEST_F(NavReaderTest, RowsWithoutImageAreNavigationSamples) {
  const NavTable table = Read("time_s,image,lat,lon,alt\n0,,43,131,2\n1,a.jpg,43,131,2\n,b.jpg,43,131,2\n");
  ASSERT_EQ(table.records.size(), 2u);
  EXPECT_TRUE(table.has_images);
  EXPECT_EQ(table.records[0].image, "");
  EXPECT_EQ(RejectionAt(table, 4).field, "time_s");
}

TEST_F(NavReaderTest, ATimeColumnEmptyOnEveryRowIsNoTimeColumn) {
  // trajectory.csv of navigation without times keeps its fixed header.
  const NavTable table = Read("image,time_s,lat,lon,alt\na.jpg,,43,131,2\nb.jpg, ,43,131,2\n");
  ASSERT_EQ(table.records.size(), 2u);
  EXPECT_TRUE(table.rejected.empty());
  EXPECT_FALSE(table.has_times);
  EXPECT_FALSE(table.records[1].time_s.has_value());
  // Without images, nothing says which frame a row is.
  const InputError e = Fatal("time_s,lat,lon,alt\n,43,131,2\n");
  EXPECT_EQ(e.field(), "image");
}

TEST_F(NavReaderTest, IsoTimestamps) {
  const NavTable table = Read("timestamp,image,lat,lon,alt\n2023-05-01T12:00:00.5Z,a.jpg,43,131,2\n");
  EXPECT_DOUBLE_EQ(*table.records[0].time_s, 1682942400.5);
}

TEST_F(NavReaderTest, ImplausibleValuesRejectTheLineNamingTheField) {
  // Finite but physically impossible: each line is skipped, the rest is read.
  const std::string path = Write(
      "image,time_s,x_m,y_m,alt,depth,heading,pitch,roll\n"  // 1
      "a.jpg,0,1,2,1.6,30,1e300,0,0\n"                       // 2 good: any finite heading, normalised
      "b.jpg,1,1e308,2,1.6,30,0,0,0\n"                       // 3
      "c.jpg,2,1,-4e6,1.6,30,0,0,0\n"                        // 4
      "d.jpg,3,1,2,1e9,30,0,0,0\n"                           // 5
      "e.jpg,4,1,2,1000,30,0,0,0\n"                          // 6 good: 1 km above the seabed
      "f.jpg,5,1,2,1.6,1e6,0,0,0\n"                          // 7
      "g.jpg,6,1,2,1.6,-2000,0,0,0\n"                        // 8
      "h.jpg,1e300,1,2,1.6,30,0,0,0\n"                       // 9
      "i.jpg,7,1,2,1.6,30,0,-90,0\n"                         // 10
      "j.jpg,8,1,2,1.6,30,0,0,1e308\n");                     // 11
  const NavTable table = ReadNavigation(path, WithOrigin(43.1, 131.9));
  ASSERT_EQ(table.records.size(), 2u);
  EXPECT_GE(table.records[0].pose.heading_deg, 0);
  EXPECT_LT(table.records[0].pose.heading_deg, 360);
  EXPECT_DOUBLE_EQ(table.records[1].pose.altitude_m, 1000);
  struct Case {
    int line;
    std::string field, words;
  };
  for (const Case& c : std::vector<Case>{{3, "x_m", "x_m must be within +-3000000 m, got 1e+308"},
                                         {4, "y_m", "y_m must be within +-3000000 m"},
                                         {5, "altitude_m", "altitude_m must be at most 1000 m"},
                                         {7, "depth_m", "depth_m must be within [-1000, 12000], got 1000000"},
                                         {8, "depth_m", "got -2000"},
                                         {9, "time_s", "time_s must be within +-1e+13 s"},
                                         {10, "pitch_deg", "pitch_deg must be within (-90, 90), got -90"},
                                         {11, "roll_deg", "roll_deg must be within (-90, 90)"}}) {
    const Rejection r = RejectionAt(table, c.line);
    EXPECT_EQ(r.field, c.field) << "line " << c.line;
    EXPECT_TRUE(Contains(r.Message(), path + ":" + std::to_string(c.line) + ": ")) << r.Message();
    EXPECT_TRUE(Contains(r.reason, c.words)) << r.reason;
  }
  EXPECT_EQ(table.rejected.size(), 8u);
}

TEST_F(NavReaderTest, GeographicPositionsFarFromTheOriginAreRejected) {
  // 43 N 131 E is about 9,000 km from 16.5 S 180 E: no local metres there.
  const NavTable table = Read("image,lat,lon,alt\na.jpg,43.1,131.9,2\nb.jpg,-16.5,179.9,2\nc.jpg,43.1001,131.9,2\n");
  ASSERT_EQ(table.records.size(), 2u);
  const Rejection r = RejectionAt(table, 3);
  EXPECT_EQ(r.field, "lat/lon");
  EXPECT_TRUE(Contains(r.reason, "km from the origin 43.1,131.9 (limit 3000 km)")) << r.reason;
}

TEST_F(NavReaderTest, LongLinesAndNamesCostNoMoreThanTheFile) {
  // A 10 MB unknown column name was copied into every line's message (8 GB
  // for 800 lines); now the header is refused at once, naming its line.
  const std::string huge(10 << 20, 'c');
  const InputError e = Fatal("image,x_m,y_m,alt," + huge + "\na.jpg,1,2,1.5\n", WithOrigin(43.1, 131.9));
  EXPECT_EQ(e.line(), 1);
  EXPECT_LT(std::string(e.what()).size(), 300u);
  // A 10 MB line among good ones is skipped with its length, the rest is read.
  const std::string path = Write("image,x_m,y_m,alt\na.jpg,1,2,1.5\nb.jpg,1,2," + huge + "\nc.jpg,1,2,1.5\n");
  const NavTable table = ReadNavigation(path, WithOrigin(43.1, 131.9));
  EXPECT_EQ(table.records.size(), 2u);
  const Rejection r = RejectionAt(table, 3);
  EXPECT_TRUE(Contains(r.reason, "line is 10485770 bytes long (limit 65536)")) << r.reason;
  // Values quoted in messages are shortened.
  const NavTable bad =
      Read("image,x_m,y_m,alt\na.jpg,1,2," + std::string(3000, 'x') + "\nb.jpg,1,2,2\n", WithOrigin(43.1, 131.9));
  EXPECT_LT(RejectionAt(bad, 2).reason.size(), 200u) << RejectionAt(bad, 2).reason;
}

}  // namespace
}  // namespace seamap
