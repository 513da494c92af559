// A real AUV log as it comes (ACFR's Sirius over a Tasmanian reef,
// data/acfr_sirius_freycinet_nav_head.csv: the UTC time split over six
// columns, angles in radians, stereo image names), read through the shipped
// config/acfr_auv_nav.json: `seamap simulate --path` renders frames at its
// first poses, named as it names them, and `seamap build` must place each
// where the log says.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;
namespace fs = std::filesystem;

const std::string kLog = std::string(SEAMAP_SOURCE_DIR) + "/data/acfr_sirius_freycinet_nav_head.csv";
const std::string kConfig = std::string(SEAMAP_SOURCE_DIR) + "/config/acfr_auv_nav.json";
constexpr int kRows = 30;  // 30 s of the dive: 9 m of track, altitude 2.0-3.9 m

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The log's lines as written: the header, then kRows rows split on ','.
std::vector<std::vector<std::string>> LogRows(std::string* header) {
  std::ifstream in(kLog);
  std::string line;
  std::getline(in, *header);
  std::vector<std::vector<std::string>> rows;
  while (rows.size() < kRows && std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream split(line);
    for (std::string field; std::getline(split, field, ',');) fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

std::string Join(const std::vector<std::string>& fields) {
  std::string out;
  for (const auto& f : fields) out += (out.empty() ? "" : ",") + f;
  return out;
}

// The first kRows rows, times possibly rewritten, written as a log file.
std::string WriteLog(const fs::path& path, const std::vector<std::vector<std::string>>& rows,
                     const std::string& header) {
  std::string text = header + "\n";
  for (const auto& row : rows) text += Join(row) + "\n";
  return testing::WriteFile(path, text).string();
}

// Columns of the ACFR log (data/README.md).
enum Column {
  kYear,
  kMonth,
  kDay,
  kHour,
  kMinute,
  kSecond,
  kNorthing,
  kEasting,
  kDepth,
  kLat,
  kLon,
  kRoll,
  kPitch,
  kHeading,
  kAltitude,
  kLeftImage,
  kRightImage
};

// Simulated once: frames at the log's first kRows poses, small images.
struct RealLogSurvey {
  testing::TempDir dir;
  std::string header, log, sim, map;
  std::vector<std::vector<std::string>> rows;
  std::string simulate_output, build_output;
  int simulate_rc = -1, build_rc = -1;
};

const RealLogSurvey& Survey() {
  static RealLogSurvey* survey = [] {
    auto* s = new RealLogSurvey;
    s->rows = LogRows(&s->header);
    s->log = WriteLog(s->dir / "head.csv", s->rows, s->header);
    s->sim = (s->dir / "sim").string();
    s->map = (s->dir / "m.mbtiles").string();
    s->simulate_rc = Seamap("simulate --path " + s->log + " --config " + kConfig + " --out " + s->sim +
                                " --width 320 --height 240 --focal-mm 4 --quiet",
                            &s->simulate_output);
    s->build_rc = Seamap("build --images " + s->sim + "/photo --nav " + s->log + " --config " + kConfig + " --camera " +
                             s->sim + "/camera.json --out " + s->map + " --quiet",
                         &s->build_output);
    return s;
  }();
  return *survey;
}

TEST(RealNavLog, FramesArePlacedWhereTheLogSays) {
  const RealLogSurvey& s = Survey();
  ASSERT_EQ(s.simulate_rc, 0) << s.simulate_output;
  ASSERT_EQ(s.build_rc, 0) << s.build_output;
  EXPECT_TRUE(Contains(s.build_output, "frames used 30, rejected 0")) << s.build_output;
  EXPECT_FALSE(Contains(s.build_output, "+-pi")) << s.build_output;  // the config states radians

  // The photos are named as the log names its left images.
  for (const auto& row : s.rows)
    EXPECT_TRUE(fs::exists(fs::path(s.sim) / "photo" / row[kLeftImage])) << row[kLeftImage];

  // Every frame of the map where the log puts it: position, heading, attitude, time.
  auto store = OpenTileStore(s.map, "png", false);
  const std::vector<FrameRecord> frames = store->Records().Frames();
  ASSERT_EQ(frames.size(), s.rows.size());
  const LocalFrame local(LatLon{std::stod(s.rows[0][kLat]), std::stod(s.rows[0][kLon])});
  double worst_m = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    const FrameRecord& f = frames[i];
    const auto& row = s.rows[i];
    EXPECT_EQ(f.image, row[kLeftImage]);
    EXPECT_EQ(f.status, "used") << f.image;
    const LocalXY want = local.FromLatLon({std::stod(row[kLat]), std::stod(row[kLon])});
    const LocalXY got = local.FromLatLon(f.position);
    worst_m = std::max(worst_m, std::hypot(got.east - want.east, got.north - want.north));
    const double heading_deg = std::fmod(std::stod(row[kHeading]) * 180 / M_PI + 360, 360);
    EXPECT_NEAR(std::remainder(f.heading_deg - heading_deg, 360), 0, 1e-4) << f.image;
    EXPECT_NEAR(f.pitch_deg, std::stod(row[kPitch]) * 180 / M_PI, 1e-4) << f.image;
    EXPECT_NEAR(f.roll_deg, std::stod(row[kRoll]) * 180 / M_PI, 1e-4) << f.image;
    EXPECT_NEAR(f.altitude_m, std::stod(row[kAltitude]), 1e-6) << f.image;
    ASSERT_TRUE(f.time_s) << f.image;
    // 2009-06-11 06:54:20.38 UTC is 1244703260.38 s after 1970; one row a second.
    const double want_time_s = 1244703260.38 + (std::stoi(row[kMinute]) - 54) * 60 + std::stod(row[kSecond]) - 20.38;
    EXPECT_NEAR(*f.time_s, want_time_s, 1e-4) << f.image;
  }
  EXPECT_LT(worst_m, 0.005) << "a frame's position is off the log's latitude, longitude";

  // The photos land on the seabed where they were taken: map-eval against the simulator's truth.
  const std::string json = (s.dir / "eval.json").string();
  std::string log;
  ASSERT_EQ(Seamap("map-eval " + s.map + " " + s.sim + " --json " + json, &log), 0) << log;
  std::ifstream in(json);
  const nlohmann::json eval = nlohmann::json::parse(in);
  EXPECT_GT(eval.at("measured_blocks").get<int>(), 30) << log;
  EXPECT_LT(eval.at("median_px").get<double>(), 1.0) << log;
  EXPECT_LT(eval.at("p90_px").get<double>(), 2.0) << log;
}

TEST(RealNavLog, RadiansWithoutAngleUnitAreWarnedAbout) {
  const RealLogSurvey& s = Survey();
  ASSERT_EQ(s.simulate_rc, 0) << s.simulate_output;
  nlohmann::json config = nlohmann::json::parse(std::ifstream(kConfig));
  config["navigation"].erase("angle_unit");
  testing::TempDir dir;
  const std::string config_path = testing::WriteFile(dir / "c.json", config.dump()).string();
  std::string log;
  ASSERT_EQ(Seamap("build --images " + s.sim + "/photo --nav " + s.log + " --config " + config_path + " --camera " +
                       s.sim + "/camera.json --out " + (dir / "m").string() + " --quiet",
                   &log),
            0)
      << log;
  EXPECT_TRUE(Contains(log, "head.csv:1: headings never leave +-pi")) << log;
  EXPECT_TRUE(Contains(log, "\"angle_unit\": \"radians\"")) << log;
}

TEST(RealNavLog, SplitDateAndTimeAcrossMidnight) {
  // The same rows, their clock moved to 23:59:45 on 11 June: the 16th row is 00:00:00.38 on the 12th.
  const RealLogSurvey& s = Survey();
  ASSERT_EQ(s.simulate_rc, 0) << s.simulate_output;
  std::vector<std::vector<std::string>> rows = s.rows;
  for (size_t i = 0; i < rows.size(); ++i) {
    const int second = 45 + static_cast<int>(i);
    const bool next_day = second >= 60;
    rows[i][kDay] = next_day ? "12" : "11";
    rows[i][kHour] = next_day ? "0" : "23";
    rows[i][kMinute] = next_day ? "0" : "59";
    rows[i][kSecond] = std::to_string(second % 60) + ".38";
  }
  testing::TempDir dir;
  const std::string log_path = WriteLog(dir / "late.csv", rows, s.header);
  const std::string map = (dir / "m.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap("build --images " + s.sim + "/photo --nav " + log_path + " --config " + kConfig + " --camera " +
                       s.sim + "/camera.json --out " + map + " --quiet",
                   &log),
            0)
      << log;
  EXPECT_FALSE(Contains(log, "backwards")) << log;
  EXPECT_FALSE(Contains(log, "midnight")) << log;  // the date is there: nothing to guess
  auto store = OpenTileStore(map, "png", false);
  const std::vector<FrameRecord> frames = store->Records().Frames();
  ASSERT_EQ(frames.size(), rows.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    ASSERT_TRUE(frames[i].time_s);
    // 2009-06-11 23:59:45.38 UTC = 1244764785.38 s.
    EXPECT_NEAR(*frames[i].time_s, 1244764785.38 + static_cast<double>(i), 1e-4) << frames[i].image;
  }

  // Without the date, the time of day is carried into the next day, and the warning says so.
  nlohmann::json config = nlohmann::json::parse(std::ifstream(kConfig));
  for (const char* part : {"year", "month", "day"}) config["navigation"]["time_columns"].erase(part);
  const std::string config_path = testing::WriteFile(dir / "c.json", config.dump()).string();
  ASSERT_EQ(Seamap("build --images " + s.sim + "/photo --nav " + log_path + " --config " + config_path + " --camera " +
                       s.sim + "/camera.json --out " + (dir / "clock").string() + " --quiet",
                   &log),
            0)
      << log;
  EXPECT_TRUE(Contains(log, "late.csv:17: the time of day passes midnight")) << log;
  EXPECT_FALSE(Contains(log, "backwards")) << log;
}

TEST(RealNavLog, BadConfigValuesAreRefusedNamingTheField) {
  const RealLogSurvey& s = Survey();
  ASSERT_EQ(s.simulate_rc, 0) << s.simulate_output;
  const nlohmann::json base = nlohmann::json::parse(std::ifstream(kConfig));
  struct Case {
    std::string key;  // under "navigation"
    nlohmann::json value;
    std::string field;  // as the message must name it
  };
  const nlohmann::json parts = base["navigation"]["time_columns"];
  nlohmann::json missing_column = parts, not_a_string = parts, unknown_part = parts;
  missing_column["hour"] = "HH";
  not_a_string["hour"] = 4;
  unknown_part["week"] = "week";
  const std::vector<Case> cases = {
      {"angle_unit", "gradians", "navigation.angle_unit"},
      {"angle_unit", 1, "navigation.angle_unit"},
      {"time_columns", "year,month", "navigation.time_columns"},
      {"time_columns", nlohmann::json::object(), "navigation.time_columns"},
      {"time_columns", {{"year", "year"}, {"hour", "hour"}}, "navigation.time_columns"},
      {"time_columns", unknown_part, "navigation.time_columns"},
      {"time_columns", not_a_string, "navigation.time_columns.hour"},
      {"time_columns", missing_column, "navigation.time_columns.hour"},
      {"columns", {{"image", "leftimage"}, {"time_s", "second"}}, "navigation.time_columns"},
  };
  testing::TempDir dir;
  for (const Case& c : cases) {
    nlohmann::json config = base;
    config["navigation"][c.key] = c.value;
    const std::string config_path = testing::WriteFile(dir / "c.json", config.dump()).string();
    for (const std::string& command : {"build --images " + s.sim + "/photo --nav " + s.log + " --camera " + s.sim +
                                           "/camera.json --out " + (dir / "m").string(),
                                       "simulate --path " + s.log + " --out " + (dir / "sim").string()}) {
      std::string log;
      EXPECT_EQ(Seamap(command + " --config " + config_path + " --quiet", &log), 2) << c.value.dump() << "\n" << log;
      EXPECT_TRUE(Contains(log, c.field)) << c.value.dump() << "\n" << log;
      EXPECT_LT(log.size(), 1200u) << log;
    }
  }
}

TEST(RealNavLog, SimulateRefusesImageNamesItCannotRender) {
  // A log in local metres (--origin) naming its images: each bad name is refused, naming the line.
  testing::TempDir dir;
  const std::string good = "a.png,0,0,2,10\nb.png,0.2,0,2,10\n";
  for (const auto& [rows, reason] :
       std::vector<std::pair<std::string, std::string>>{{good + "photo/c.png,0.4,0,2,10\n", "plain file name"},
                                                        {good + "c.tif,0.4,0,2,10\n", ".png, .jpg or .jpeg"},
                                                        {good + "a.png,0.4,0,2,10\n", "named twice"}}) {
    const std::string log_path =
        testing::WriteFile(dir / "log.csv", "image,x_m,y_m,altitude_m,heading\n" + rows).string();
    std::string log;
    EXPECT_EQ(Seamap("simulate --path " + log_path + " --origin 43.1,131.9 --out " + (dir / "sim").string() +
                         " --width 160 --height 120 --quiet",
                     &log),
              2)
        << log;
    EXPECT_TRUE(Contains(log, "log.csv:4: field 'image'")) << log;
    EXPECT_TRUE(Contains(log, reason)) << log;
  }
  // The good rows render, named as the log names them.
  const std::string log_path =
      testing::WriteFile(dir / "log.csv", "image,x_m,y_m,altitude_m,heading\n" + good).string();
  std::string log;
  ASSERT_EQ(Seamap("simulate --path " + log_path + " --origin 43.1,131.9 --out " + (dir / "sim").string() +
                       " --width 160 --height 120 --quiet",
                   &log),
            0)
      << log;
  EXPECT_TRUE(fs::exists(dir / "sim" / "photo" / "b.png"));
  EXPECT_FALSE(Contains(log, "+-pi")) << log;  // 10 is beyond pi
}

}  // namespace
}  // namespace seamap
