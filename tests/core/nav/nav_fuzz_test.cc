// Randomised navigation, image-times and CSV input (tests/testing/fuzz.h):
// whatever the bytes, the readers either stop with an InputError naming the
// file, or return records whose every value is finite and plausible, with
// each skipped line reported by file and line. Never a crash, a hang or a
// value that makes the map unopenable.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "core/nav/csv_table.h"
#include "core/nav/frame_list.h"
#include "core/nav/nav_limits.h"
#include "core/nav/nav_reader.h"
#include "core/util/error.h"
#include "tests/testing/fuzz.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::Fuzz;
using testing::TempDir;

const std::vector<std::string> kHeader = {"image",   "time_s",      "x_m",       "y_m",     "altitude_m",
                                          "depth_m", "heading_deg", "pitch_deg", "roll_deg"};

std::string ValidLine(int i) {
  return "f" + std::to_string(i) + ".png," + std::to_string(i * 0.5) + "," + std::to_string(i * 0.1) + ",0.5,2.0,30," +
         std::to_string(i % 360) + ",1.5,-2";
}

// A navigation CSV with some fields replaced by hostile values and some
// lines mangled byte by byte.
std::string HostileNav(Fuzz& fuzz) {
  std::string header;
  for (const auto& h : kHeader) header += (header.empty() ? "" : ",") + h;
  if (fuzz.OneIn(20)) header = fuzz.Mutate(header);
  std::string text = header + "\n";
  const int lines = 1 + static_cast<int>(fuzz.Below(30));
  for (int i = 0; i < lines; ++i) {
    std::vector<std::string> fields;
    std::string line = ValidLine(i);
    for (size_t start = 0;;) {
      const size_t comma = line.find(',', start);
      fields.push_back(line.substr(start, comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (fuzz.OneIn(3)) fields[fuzz.Below(fields.size())] = fuzz.HostileNumber();
    line.clear();
    for (const auto& f : fields) line += (line.empty() ? "" : ",") + f;
    if (fuzz.OneIn(6)) line = fuzz.Mutate(line);
    if (fuzz.OneIn(50)) line = std::string(kMaxLineBytes + fuzz.Below(1000), 'x');
    if (fuzz.OneIn(50)) line += "," + std::string(kMaxFieldBytes + 1, '1');
    text += line + (fuzz.OneIn(10) ? "\r\n" : "\n");
  }
  return text;
}

TEST(NavFuzz, HostileNavigationIsReadOrRefusedByName) {
  TempDir dir;
  Fuzz fuzz;
  const std::string path = (dir / "nav.csv").string();
  NavReadOptions options;
  options.origin = LatLon{43.1, 131.9};
  int read = 0, refused = 0;
  while (fuzz.More()) {
    const std::string text = HostileNav(fuzz);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    SCOPED_TRACE("case " + std::to_string(fuzz.cases()));
    try {
      const NavTable table = ReadNavigation(path, options);
      ++read;
      for (const NavRecord& r : table.records) {
        const VehiclePose& p = r.pose;
        EXPECT_TRUE(std::isfinite(p.east_m) && std::fabs(p.east_m) <= nav_limits::kMaxLocalM) << p.east_m;
        EXPECT_TRUE(std::isfinite(p.north_m) && std::fabs(p.north_m) <= nav_limits::kMaxLocalM) << p.north_m;
        EXPECT_TRUE(p.altitude_m > 0 && p.altitude_m <= nav_limits::kMaxAltitudeM) << p.altitude_m;
        EXPECT_TRUE(p.depth_m >= nav_limits::kMinDepthM && p.depth_m <= nav_limits::kMaxDepthM) << p.depth_m;
        EXPECT_TRUE(std::isfinite(p.heading_deg)) << p.heading_deg;
        EXPECT_LT(std::fabs(p.pitch_deg), nav_limits::kMaxAttitudeDeg);
        EXPECT_LT(std::fabs(p.roll_deg), nav_limits::kMaxAttitudeDeg);
        if (r.time_s) {
          EXPECT_LE(std::fabs(*r.time_s), nav_limits::kMaxAbsTimeS);
        }
        EXPECT_LE(r.image.size(), kMaxFieldBytes);
        EXPECT_GT(r.line, 1);
      }
      for (const Rejection& j : table.rejected) {
        EXPECT_EQ(j.file, path);
        EXPECT_GT(j.line, 1) << j.Message();
        EXPECT_FALSE(j.reason.empty());
        EXPECT_LE(j.Message().size(), 2000u) << "messages stay short: " << j.Message().substr(0, 200);
      }
      // Every data line is a record or a rejection, never silently dropped.
      EXPECT_LE(table.records.size() + table.rejected.size(),
                static_cast<size_t>(std::count(text.begin(), text.end(), '\n')));
    } catch (const InputError& e) {
      ++refused;
      EXPECT_EQ(e.file(), path) << e.what();
      EXPECT_LE(std::string(e.what()).size(), 2000u);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what() << "\n" << text.substr(0, 2000);
    }
  }
  EXPECT_GT(read, 0);
  std::printf("nav fuzz: %d cases (%d read, %d refused), seed %u\n", fuzz.cases() - 1, read, refused, fuzz.seed());
}

// Raw bytes through the CSV layer: lines and fields stay within their bounds
// and a long line is reported, not kept.
TEST(NavFuzz, CsvLinesAndFieldsStayBounded) {
  TempDir dir;
  Fuzz fuzz;
  const std::string path = (dir / "table.csv").string();
  while (fuzz.More()) {
    std::string text = "a,b;c\td \"e\"\n";
    const int parts = 1 + static_cast<int>(fuzz.Below(40));
    for (int i = 0; i < parts; ++i) {
      if (fuzz.OneIn(40))
        text += std::string(kMaxLineBytes + fuzz.Below(3000), fuzz.OneIn(2) ? '"' : ',');
      else if (fuzz.OneIn(40))
        text += std::string(kMaxFieldBytes + fuzz.Below(100), 'q');
      else
        text += fuzz.Bytes(60);
      if (fuzz.OneIn(2)) text += "\n";
    }
    if (fuzz.OneIn(4)) text = fuzz.Mutate(text);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    SCOPED_TRACE("case " + std::to_string(fuzz.cases()));
    try {
      const CsvTable table = ParseCsv(ReadTextLines(path), path);
      size_t bytes = 0;
      for (const auto& h : table.header) EXPECT_LE(h.size(), kMaxFieldBytes);
      for (const CsvRow& row : table.rows) {
        if (!row.problem.empty()) {
          EXPECT_TRUE(row.fields.empty());
        }
        for (const auto& f : row.fields) {
          EXPECT_LE(f.size(), kMaxFieldBytes);
          bytes += f.size();
        }
        EXPECT_LE(row.problem.size(), 1000u);
      }
      EXPECT_LE(bytes, text.size());
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what();
    }
    for (char sep : {',', ';', '\t', ' '}) {
      const std::string line = fuzz.Bytes(200);
      const auto fields = SplitFields(line, sep);
      size_t total = 0;
      for (const auto& f : fields) total += f.size();
      EXPECT_LE(total, line.size());
    }
  }
}

// Image times (image,time_s) with hostile times: out-of-span or implausible
// times are reported by line, never matched to a pose.
TEST(NavFuzz, HostileImageTimesAreReportedByLine) {
  TempDir dir;
  Fuzz fuzz;
  NavReadOptions options;
  options.origin = LatLon{43.1, 131.9};
  std::string nav = "time_s,x_m,y_m,altitude_m,heading_deg\n";
  for (int i = 0; i <= 20; ++i) nav += std::to_string(i) + "," + std::to_string(0.1 * i) + ",0,2,0\n";
  const std::string nav_path = testing::WriteFile(dir / "nav.csv", nav).string();
  const NavTable table = ReadNavigation(nav_path, options);
  const std::string times_path = (dir / "times.csv").string();
  while (fuzz.More()) {
    std::string text = "image,time_s\n";
    const int lines = 1 + static_cast<int>(fuzz.Below(20));
    for (int i = 0; i < lines; ++i) {
      std::string t = fuzz.OneIn(2) ? fuzz.HostileNumber() : std::to_string(fuzz.Below(25));
      std::string line = "f" + std::to_string(i) + ".png," + t;
      if (fuzz.OneIn(8)) line = fuzz.Mutate(line);
      text += line + "\n";
    }
    std::ofstream(times_path, std::ios::binary | std::ios::trunc) << text;
    SCOPED_TRACE("case " + std::to_string(fuzz.cases()));
    try {
      const FrameList frames = MatchFrames(table, (dir / "photo").string(), times_path);
      for (const FrameSpec& f : frames.frames) {
        ASSERT_TRUE(f.time_s);
        EXPECT_GE(*f.time_s, 0);
        EXPECT_LE(*f.time_s, 20);
        EXPECT_TRUE(std::isfinite(f.pose.east_m));
      }
      for (const Rejection& r : frames.rejected) EXPECT_GT(r.line, 1) << r.Message();
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), times_path) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what();
    }
  }
}

}  // namespace
}  // namespace seamap
