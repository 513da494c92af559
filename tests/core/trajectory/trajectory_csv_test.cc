#include "core/trajectory/trajectory_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/nav/nav_reader.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;

const LatLon kOrigin{43.1, 131.9};

std::string FirstLine(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

NavReadOptions WithOrigin(LatLon origin) {
  NavReadOptions options;
  options.origin = origin;
  return options;
}

// Heading on the circle: 359.9999999 and 0 are the same direction.
double AngleGap(double a, double b) {
  const double d = std::fmod(std::fabs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}

std::vector<TrajectoryRow> SampleRows() {
  std::vector<TrajectoryRow> rows;
  for (int i = 0; i < 50; ++i) {
    TrajectoryRow r;
    r.image = "frame_" + std::to_string(i) + ".jpg";
    r.time_s = 1700000000.0 + 0.2 * i;
    // Far from the origin and with sub-millimetre digits, to test the precision.
    r.pose.east_m = -812.34567 + 13.1234567 * i;
    r.pose.north_m = 1234.56789 - 7.7654321 * i;
    r.pose.altitude_m = 1.6 + 0.0123456 * i;
    r.pose.depth_m = 35.0 - 0.01 * i;
    r.pose.heading_deg = std::fmod(359.9999995 + 7.3 * i, 360.0);
    r.pose.pitch_deg = -3.0 + 0.1234567 * i;
    r.pose.roll_deg = 2.0 - 0.0765432 * i;
    rows.push_back(r);
  }
  return rows;
}

void ExpectSamePoses(const std::vector<TrajectoryRow>& rows, const NavTable& nav) {
  ASSERT_EQ(nav.records.size(), rows.size());
  EXPECT_TRUE(nav.rejected.empty()) << nav.rejected.front().Message();
  for (size_t i = 0; i < rows.size(); ++i) {
    const VehiclePose &a = rows[i].pose, &b = nav.records[i].pose;
    EXPECT_EQ(nav.records[i].image, rows[i].image);
    EXPECT_NEAR(a.east_m, b.east_m, 1e-4) << i;
    EXPECT_NEAR(a.north_m, b.north_m, 1e-4) << i;
    EXPECT_NEAR(a.altitude_m, b.altitude_m, 1e-4) << i;
    EXPECT_NEAR(a.depth_m, b.depth_m, 1e-4) << i;
    EXPECT_LE(AngleGap(a.heading_deg, b.heading_deg), 1e-6) << i;
    EXPECT_NEAR(a.pitch_deg, b.pitch_deg, 1e-6) << i;
    EXPECT_NEAR(a.roll_deg, b.roll_deg, 1e-6) << i;
  }
}

TEST(TrajectoryCsv, WritesTheHeaderAndRoundTripsThroughTheNavigationReader) {
  TempDir dir;
  const std::string path = (dir / "trajectory.csv").string();
  const auto rows = SampleRows();
  WriteTrajectoryCsv(path, rows, LocalFrame(kOrigin));
  EXPECT_EQ(FirstLine(path), "image,time_s,lat,lon,x_m,y_m,depth_m,altitude_m,heading_deg,pitch_deg,roll_deg");

  const NavTable nav = ReadNavigation(path, WithOrigin(kOrigin));
  ExpectSamePoses(rows, nav);
  EXPECT_TRUE(nav.has_images);
  EXPECT_TRUE(nav.has_times);
  for (size_t i = 0; i < rows.size(); ++i) {
    ASSERT_TRUE(nav.records[i].time_s.has_value());
    EXPECT_NEAR(*nav.records[i].time_s, *rows[i].time_s, 1e-6);
  }
}

TEST(TrajectoryCsv, LatLonWinsSoAnotherOriginGivesTheSamePlaces) {
  TempDir dir;
  const std::string path = (dir / "trajectory.csv").string();
  const auto rows = SampleRows();
  const LocalFrame frame(kOrigin);
  WriteTrajectoryCsv(path, rows, frame);
  // Read in another frame, as `build --nav trajectory.csv` without --origin does
  // (origin at the first row): the same geographic positions.
  const NavTable nav = ReadNavigation(path, {});
  const LocalFrame other(nav.origin);
  for (size_t i = 0; i < rows.size(); ++i) {
    const LocalXY xy = other.FromLatLon(frame.ToLatLon({rows[i].pose.east_m, rows[i].pose.north_m}));
    EXPECT_NEAR(nav.records[i].pose.east_m, xy.east, 1e-4) << i;
    EXPECT_NEAR(nav.records[i].pose.north_m, xy.north, 1e-4) << i;
  }
  EXPECT_NEAR(nav.records[0].pose.east_m, 0, 1e-4);
}

TEST(TrajectoryCsv, FlagsColumnOnlyWhenSomeRowHasFlagsAndTheReaderIgnoresIt) {
  TempDir dir;
  const std::string path = (dir / "trajectory.csv").string();
  auto rows = SampleRows();
  rows[3].flags = "nav_only";
  rows[4].flags = "nav_only;gated";
  WriteTrajectoryCsv(path, rows, LocalFrame(kOrigin));
  EXPECT_EQ(FirstLine(path), "image,time_s,lat,lon,x_m,y_m,depth_m,altitude_m,heading_deg,pitch_deg,roll_deg,flags");

  const NavTable nav = ReadNavigation(path, WithOrigin(kOrigin));
  ExpectSamePoses(rows, nav);  // rows without flags end in an empty field: accepted
  bool warned = false;
  for (const auto& w : nav.warnings) warned = warned || w.find("ignoring unknown columns: flags") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(TrajectoryCsv, RowsWithoutTimeKeepAnEmptyCellThatReadsBackAsNoTime) {
  TempDir dir;
  const std::string path = (dir / "trajectory.csv").string();
  auto rows = SampleRows();
  for (auto& r : rows) r.time_s.reset();
  WriteTrajectoryCsv(path, rows, LocalFrame(kOrigin));
  const NavTable nav = ReadNavigation(path, WithOrigin(kOrigin));
  ExpectSamePoses(rows, nav);
  EXPECT_FALSE(nav.has_times);
  for (const auto& r : nav.records) EXPECT_FALSE(r.time_s.has_value());
}

TEST(TrajectoryCsv, OddImageNamesAreQuoted) {
  TempDir dir;
  const std::string path = (dir / "trajectory.csv").string();
  auto rows = SampleRows();
  rows.resize(3);
  rows[0].image = "dive 3, leg 2.jpg";
  rows[1].image = "say \"cheese\".jpg";
  rows[2].image = "a;b.jpg";
  WriteTrajectoryCsv(path, rows, LocalFrame(kOrigin));
  ExpectSamePoses(rows, ReadNavigation(path, WithOrigin(kOrigin)));
}

TEST(TrajectoryCsv, RefusesRowsItCouldNotReadBack) {
  TempDir dir;
  const std::string path = (dir / "trajectory.csv").string();
  auto rows = SampleRows();
  rows[2].image.clear();
  rows[2].time_s.reset();
  try {
    WriteTrajectoryCsv(path, rows, LocalFrame(kOrigin));
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 4);  // header, then rows 0, 1, 2
    EXPECT_EQ(e.field(), "image");
  }
  rows = SampleRows();
  rows[1].image = "two\nlines.jpg";
  EXPECT_THROW(WriteTrajectoryCsv(path, rows, LocalFrame(kOrigin)), InputError);
  EXPECT_THROW(WriteTrajectoryCsv((dir / "no/such/folder/t.csv").string(), SampleRows(), LocalFrame(kOrigin)),
               InputError);
}

}  // namespace
}  // namespace seamap
