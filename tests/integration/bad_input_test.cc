// Bad input never crashes the build, never corrupts a map and is never
// dropped silently: frame-level problems skip the frame and are counted;
// file-level problems stop with a message naming file, line and field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;
using testing::SharedSurvey;
namespace fs = std::filesystem;

const testing::SimulatedSurvey& Survey() {
  return SharedSurvey("bad_input", "--frames 12 --line-length 2 --seed 3");
}

// A private copy of the survey that a test may damage.
struct DamagedSurvey {
  testing::TempDir dir;
  std::string photo, nav, camera;
  DamagedSurvey() {
    fs::copy(Survey().dir, dir.path() / "s", fs::copy_options::recursive);
    photo = (dir.path() / "s/photo").string();
    nav = (dir.path() / "s/nav.csv").string();
    camera = (dir.path() / "s/camera.json").string();
  }
  std::string Args(const std::string& out) const {
    return "build --quiet --images " + photo + " --nav " + nav + " --camera " + camera + " --origin 43.1,131.9 --out " +
           out;
  }
  std::vector<std::string> NavLines() const {
    std::ifstream in(nav);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
  }
  void WriteNav(const std::vector<std::string>& lines) const {
    std::ofstream out(nav);
    for (const auto& l : lines) out << l << "\n";
  }
  std::string Image(int i) const {
    std::ostringstream s;
    s << photo << "/frame_" << std::setw(6) << std::setfill('0') << i << ".png";
    return s.str();
  }
};

TEST(BadInput, MissingAndBrokenImagesAreSkippedAndCounted) {
  DamagedSurvey s;
  fs::remove(s.Image(2));
  {  // truncated PNG
    std::ifstream in(s.Image(4), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(s.Image(4), std::ios::binary) << bytes.substr(0, bytes.size() / 3);
  }
  std::ofstream(s.Image(6)) << "not an image";
  const std::string out = (s.dir / "m.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(s.Args(out), &log), 0) << log;
  EXPECT_NE(log.find("frames used 9, rejected 3"), std::string::npos) << log;
  EXPECT_NE(log.find("missing image"), std::string::npos) << log;
  EXPECT_NE(log.find("frame_000002.png"), std::string::npos) << log;
  EXPECT_NE(log.find("unreadable image"), std::string::npos) << log;
  auto store = OpenTileStore(out, "png", false);
  auto frames = store->Records().Frames();
  ASSERT_EQ(frames.size(), 12u);
  EXPECT_EQ(frames[2].status, "missing image");
}

TEST(BadInput, BadNavigationLinesAreSkippedWithFileLineAndField) {
  DamagedSurvey s;
  auto lines = s.NavLines();
  ASSERT_GE(lines.size(), 13u);
  // Columns: image,time_s,x_m,y_m,altitude_m,depth_m,heading_deg,pitch_deg,roll_deg
  auto replace_field = [](std::string line, int field, const std::string& value) {
    size_t start = 0;
    for (int i = 0; i < field; ++i) start = line.find(',', start) + 1;
    size_t end = line.find(',', start);
    return line.substr(0, start) + value + (end == std::string::npos ? "" : line.substr(end));
  };
  lines[2] = replace_field(lines[2], 4, "-1.5");                              // altitude <= 0 (file line 3)
  lines[3] = replace_field(lines[3], 6, "nan");                               // heading not finite (line 4)
  lines[4] = lines[4].substr(0, lines[4].find(',', lines[4].find(',') + 1));  // missing columns (line 5)
  lines[5] = replace_field(lines[5], 2,
                           "\xE2\x88\x92"
                           "0.25");  // Unicode minus: accepted (line 6)
  s.WriteNav(lines);
  const std::string out = (s.dir / "m.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(s.Args(out), &log), 0) << log;
  EXPECT_NE(log.find("frames used 9, rejected 3"), std::string::npos) << log;
  EXPECT_NE(log.find("nav.csv:3"), std::string::npos) << log;
  EXPECT_NE(log.find("altitude_m"), std::string::npos) << log;
  EXPECT_NE(log.find("nav.csv:4"), std::string::npos) << log;
  EXPECT_NE(log.find("heading_deg"), std::string::npos) << log;
  EXPECT_NE(log.find("nav.csv:5"), std::string::npos) << log;
}

TEST(BadInput, EmptyNavigationStopsWithTheFileName) {
  DamagedSurvey s;
  std::ofstream(s.nav, std::ios::trunc).close();
  std::string log;
  EXPECT_EQ(Seamap(s.Args((s.dir / "m.mbtiles").string()), &log), 2) << log;
  EXPECT_NE(log.find("nav.csv"), std::string::npos) << log;
  EXPECT_NE(log.find("empty"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(s.dir / "m.mbtiles"));
}

TEST(BadInput, UnwritableOutputIsNamed) {
  DamagedSurvey s;
  std::string log;
  EXPECT_EQ(Seamap(s.Args("/proc/seamap_cannot_write_here/m.mbtiles"), &log), 2) << log;
  EXPECT_NE(log.find("/proc/seamap_cannot_write_here/m.mbtiles"), std::string::npos) << log;
}

TEST(BadInput, MissingOptionAndBadOriginAreNamed) {
  DamagedSurvey s;
  std::string log;
  EXPECT_EQ(Seamap("build --quiet --images " + s.photo + " --nav " + s.nav + " --out x.mbtiles", &log), 2);
  EXPECT_NE(log.find("--camera"), std::string::npos) << log;
  EXPECT_EQ(Seamap(s.Args("x.mbtiles") + " --origin 95,10", &log), 2);
  EXPECT_NE(log.find("--origin"), std::string::npos) << log;
  EXPECT_EQ(Seamap(s.Args("x.mbtiles") + " --tile-sise 256", &log), 2);
  EXPECT_NE(log.find("--tile-sise"), std::string::npos) << log;
}

TEST(BadInput, ExistingMapIsNeverClobberedByAccident) {
  DamagedSurvey s;
  const std::string out = (s.dir / "m.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(s.Args(out), &log), 0) << log;
  const auto tiles_before = OpenTileStore(out, "png", false)->TileCount();
  EXPECT_EQ(Seamap(s.Args(out), &log), 2);
  EXPECT_NE(log.find("--append"), std::string::npos) << log;
  EXPECT_EQ(OpenTileStore(out, "png", false)->TileCount(), tiles_before);
  // --append paints on top: read back and blended, nothing lost.
  ASSERT_EQ(Seamap(s.Args(out) + " --append", &log), 0) << log;
  EXPECT_EQ(OpenTileStore(out, "png", false)->TileCount(), tiles_before);
}

}  // namespace
}  // namespace seamap
