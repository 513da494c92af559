// The hostile-input table (issue 17, "Bad input"): one case per kind of bad
// input a survey computer or a corrupted copy can hand a build. Each case
// damages a private copy of a small survey, builds it, and checks the clear
// error (file, line, field or option, and what was expected), that the
// build either finishes `complete` with a map `seamap info` opens or stops
// before creating one, and that it stayed within 600 MB (its --report).
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/hostile_png.h"

namespace seamap {
namespace {

namespace fs = std::filesystem;
using testing::SharedSurvey;

constexpr int64_t kMemoryLimitBytes = int64_t{600} << 20;

const testing::SimulatedSurvey& Survey() {
  return SharedSurvey("hostile", "--frames 12 --line-length 2 --seed 5 --quiet");
}

// A private copy of the survey that a case damages.
struct Copy {
  testing::TempDir dir;
  std::string photo, nav, camera, origin = "43.1,131.9", extra;
  Copy() {
    fs::copy(Survey().dir, dir.path() / "s", fs::copy_options::recursive);
    photo = (dir.path() / "s/photo").string();
    nav = (dir.path() / "s/nav.csv").string();
    camera = (dir.path() / "s/camera.json").string();
  }
  std::string Out() const { return (dir.path() / "m.mbtiles").string(); }
  std::string Report() const { return (dir.path() / "report.json").string(); }
  std::string Image(int i) const {
    std::ostringstream s;
    s << photo << "/frame_" << std::setw(6) << std::setfill('0') << i << ".png";
    return s.str();
  }
  std::vector<std::string> NavLines() const {
    std::ifstream in(nav);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
  }
  void WriteNav(const std::vector<std::string>& lines) const {
    std::ofstream out(nav, std::ios::trunc);
    for (const auto& l : lines) out << l << "\n";
  }
  // Sets field `field` (0-based) of file line `line` (1-based).
  void SetNavField(int line, int field, const std::string& value) const {
    auto lines = NavLines();
    std::string& l = lines.at(static_cast<size_t>(line - 1));
    size_t start = 0;
    for (int i = 0; i < field; ++i) start = l.find(',', start) + 1;
    const size_t end = l.find(',', start);
    l = l.substr(0, start) + value + (end == std::string::npos ? "" : l.substr(end));
    WriteNav(lines);
  }
};

struct Case {
  std::string name;
  std::function<void(Copy&)> damage;
  int exit_code;                                                  // 0: the build goes on and completes
  std::vector<std::string> in_log;                                // what the message must say
  std::function<void(const Copy&, const std::string& log)> also;  // further checks, may be empty
};

// gtest prints a case by its name (ctest lists it so).
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.name;
}

// x_m of the survey's frames, to put the antimeridian in its middle.
double MiddleEast(const Copy& c) {
  double lo = 1e9, hi = -1e9;
  auto lines = c.NavLines();
  for (size_t i = 1; i < lines.size(); ++i) {
    std::stringstream s(lines[i]);
    std::string field;
    for (int k = 0; k <= 2 && std::getline(s, field, ','); ++k) {
    }
    lo = std::min(lo, std::stod(field));
    hi = std::max(hi, std::stod(field));
  }
  return (lo + hi) / 2;
}

std::vector<Case> Cases() {
  return {
      {"nav x_m 1e308",
       [](Copy& c) { c.SetNavField(3, 2, "1e308"); },
       0,
       {"frames used 11, rejected 1", "nav.csv:3", "x_m", "1e+308"},
       {}},
      {"nav altitude 1e9",
       [](Copy& c) { c.SetNavField(4, 4, "1e9"); },
       0,
       {"frames used 11, rejected 1", "nav.csv:4", "altitude_m"},
       {}},
      {"nav altitude 900 m, plausible but far above the survey",
       [](Copy& c) { c.SetNavField(5, 4, "900"); },
       0,
       {"frames used 11, rejected 1", "frame too large for the map: at altitude 900 m", "memory_cap_mb"},
       {}},
      {"survey across the antimeridian",
       [](Copy& c) {
         // The issue's origin, 53 m west of the meridian; the survey moved east onto it.
         c.origin = "-16.5,179.9995";
         const double shift = 0.0005 * 111319.49 * std::cos(16.5 * M_PI / 180) - MiddleEast(c);
         auto lines = c.NavLines();
         for (size_t i = 1; i < lines.size(); ++i) {
           std::vector<std::string> f;
           std::stringstream s(lines[i]);
           for (std::string v; std::getline(s, v, ',');) f.push_back(v);
           f[2] = std::to_string(std::stod(f[2]) + shift);
           lines[i].clear();
           for (const auto& v : f) lines[i] += (lines[i].empty() ? "" : ",") + v;
         }
         c.WriteNav(lines);
       },
       0,
       {"frames used 12, rejected 0"},
       [](const Copy& c, const std::string& log) {
         auto store = OpenTileStore(c.Out(), "png", false);
         const int z = std::stoi(store->Metadata().at("maxzoom"));
         bool east = false, west = false;
         for (const TileId& id : store->TileIds()) {
           if (id.z != z) continue;
           east |= id.x < 16;
           west |= id.x >= (1 << z) - 16;
         }
         EXPECT_TRUE(east && west) << "tiles on both sides of the meridian at zoom " << z << "\n" << log;
       }},
      {"PNG header claiming 100000 x 100000",
       [](Copy& c) { testing::WriteBytes(c.Image(3), testing::ClaimingPng(100000, 100000)); },
       0,
       {"frames used 11, rejected 1", "frame_000003.png", "image too large", "100000x100000", "max_image_pixels"},
       {}},
      {"valid 875 KB PNG of 30000 x 30000 zeros",
       [](Copy& c) { testing::WriteBytes(c.Image(5), testing::ZeroPng(30000, 30000)); },
       0,
       {"frames used 11, rejected 1", "frame_000005.png", "image too large", "30000x30000"},
       {}},
      {"CSV column name of 10 MB",
       [](Copy& c) {
         auto lines = c.NavLines();
         lines[0] += "," + std::string(10 << 20, 'c');
         c.WriteNav(lines);
       },
       2,
       {"nav.csv:1", "65536"},
       {}},
      {"CSV line of 10 MB",
       [](Copy& c) {
         auto lines = c.NavLines();
         lines[6] += std::string(10 << 20, '7');
         c.WriteNav(lines);
       },
       0,
       {"frames used 11, rejected 1", "nav.csv:7", "65536"},
       {}},
      {"--base-zoom 30",
       [](Copy& c) { c.extra = "--base-zoom 30"; },
       2,
       {"base_zoom", "base zoom 30", "memory_cap_mb 512", "MB of tiles", "use --base-zoom"},
       {}},
      {"FIFO among the images",
       [](Copy& c) {
         fs::remove(c.Image(7));
         ASSERT_EQ(mkfifo(c.Image(7).c_str(), 0600), 0);
       },
       0,
       {"frames used 11, rejected 1", "frame_000007.png", "not a regular file: a FIFO"},
       {}},
      {"camera fx 1e999",
       [](Copy& c) {
         std::ifstream in(c.camera);
         nlohmann::json j = nlohmann::json::parse(in);
         std::string text = j.dump(1);
         const size_t at = text.find("\"fx\": ");
         const size_t end = text.find_first_of(",\n}", at + 6);
         text = text.substr(0, at) + "\"fx\": 1e999" + text.substr(end);
         std::ofstream(c.camera, std::ios::trunc) << text;
       },
       2,
       {"camera.json", "field 'fx'", "1e999 is out of range"},
       {}},
      {"one-colour first frame in a gray survey",
       [](Copy& c) {
         const cv::Mat red(520, 696, CV_8UC3, cv::Scalar(20, 40, 200));
         ASSERT_TRUE(cv::imwrite(c.Image(0), red));
       },
       0,
       {"frames used 12, rejected 0", "mixes gray and colour frames", "the map is gray"},
       [](const Copy& c, const std::string&) {
         auto store = OpenTileStore(c.Out(), "png", false);
         EXPECT_EQ(store->Metadata().at("seamap_channels"), "1");
       }},
  };
}

class HostileInput : public ::testing::TestWithParam<Case> {};

TEST_P(HostileInput, ClearErrorAndAMapThatOpens) {
  const Case& k = GetParam();
  Copy c;
  k.damage(c);
  if (HasFatalFailure()) return;
  // `timeout`: a build that hangs (on a FIFO) fails the case instead of the suite.
  std::string log;
  const int rc = testing::RunCommand("timeout 120 " + testing::SeamapBinary() + " build --quiet --images " + c.photo +
                                         " --nav " + c.nav + " --camera " + c.camera + " --origin " + c.origin +
                                         " --out " + c.Out() + " --report " + c.Report() + " " + c.extra,
                                     &log);
  ASSERT_EQ(rc, k.exit_code) << log.substr(0, 4000);
  for (const std::string& part : k.in_log)
    EXPECT_NE(log.find(part), std::string::npos) << part << "\n" << log.substr(0, 4000);
  EXPECT_LT(log.size(), 100000u) << "a message repeats a hostile value whole";
  if (k.exit_code == 0) {
    std::string info;
    ASSERT_EQ(testing::RunCommand(testing::SeamapBinary() + " info " + c.Out(), &info), 0) << info;
    EXPECT_NE(info.find("state:     complete"), std::string::npos) << info;
    std::ifstream report(c.Report());
    const nlohmann::json r = nlohmann::json::parse(report);
    EXPECT_LT(r.at("peak_rss_bytes").get<int64_t>(), kMemoryLimitBytes);
  } else {
    EXPECT_FALSE(fs::exists(c.Out())) << "a refused build leaves no map";
  }
  if (k.also) k.also(c, log);
}

INSTANTIATE_TEST_SUITE_P(Issue17, HostileInput, ::testing::ValuesIn(Cases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           std::string name;
                           for (char ch : info.param.name)
                             name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                           return name;
                         });

}  // namespace
}  // namespace seamap
