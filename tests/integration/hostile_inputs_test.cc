// Issue 33's input rows (9, 10, 11, 13 and part of 14), through the real
// binary on a small simulated survey: photos whose header claims a huge
// image reach no reader undecoded-checked (refine, visual odometry), files
// that declare more than they hold or are not files at all are refused by
// name, a jump in the navigation's time restarts the filter, a frozen
// camera or black photos correct nothing and say so, and georef-eval
// refuses values no survey holds. Fixtures are made here (tiny PNG headers,
// hand-written files); nothing binary is committed.
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tests/integration/survey_fixture.h"
#include "tests/testing/hostile_png.h"

namespace seamap {
namespace {

namespace fs = std::filesystem;
using testing::Seamap;
using testing::SharedSurvey;

constexpr int64_t kMemoryLimitBytes = int64_t{600} << 20;

const testing::SimulatedSurvey& Survey() {
  return SharedSurvey("h33_inputs", "--frames 24 --line-length 3 --seed 7 --quiet");
}

std::vector<std::string> Split(const std::string& line, char separator = ',') {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string v; std::getline(s, v, separator);) out.push_back(v);
  if (!line.empty() && line.back() == separator) out.push_back("");
  return out;
}

std::vector<std::string> Lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// A private copy of the survey that a test damages.
struct Copy {
  testing::TempDir dir;
  std::string photo, nav, camera, origin = "43.1,131.9";
  Copy() {
    fs::copy(Survey().dir, dir.path() / "s", fs::copy_options::recursive);
    photo = (dir.path() / "s/photo").string();
    nav = (dir.path() / "s/nav.csv").string();
    camera = (dir.path() / "s/camera.json").string();
  }
  std::string Path(const std::string& name) const { return (dir.path() / name).string(); }
  std::string Image(int i) const {
    std::ostringstream s;
    s << photo << "/frame_" << std::setw(6) << std::setfill('0') << i << ".png";
    return s.str();
  }
  std::string Inputs() const {
    return " --quiet --images " + photo + " --nav " + nav + " --camera " + camera + " --origin " + origin;
  }
  // seamap trajectory --mode `mode` into out.csv; the exit code, its output in *log.
  int Trajectory(const std::string& mode, std::string* log, const std::string& extra = "") const {
    // `timeout`: a run that hangs (predicting across 1e8 s in 0.2 s steps) fails the case, not the suite.
    return testing::RunCommand("timeout 120 " + testing::SeamapBinary() + " trajectory --mode " + mode + Inputs() +
                                   " --out " + Path("out.csv") + " " + extra,
                               log);
  }
  // The trajectory's rows by image: column -> value.
  std::map<std::string, std::map<std::string, std::string>> Rows() const {
    const auto lines = Lines(Path("out.csv"));
    std::map<std::string, std::map<std::string, std::string>> rows;
    if (lines.empty()) return rows;
    const auto header = Split(lines[0]);
    for (size_t i = 1; i < lines.size(); ++i) {
      const auto f = Split(lines[i]);
      for (size_t k = 0; k < header.size() && k < f.size(); ++k) {
        std::string v = f[k];  // "a;b" is quoted
        if (v.size() >= 2 && v.front() == '"' && v.back() == '"') v = v.substr(1, v.size() - 2);
        rows[f[0]][header[k]] = v;
      }
    }
    return rows;
  }
  // Every photo replaced by the first one: a camera that froze.
  void FreezeCamera() const {
    for (const auto& e : fs::directory_iterator(photo))
      if (e.path() != Image(0)) fs::copy_file(Image(0), e.path(), fs::copy_options::overwrite_existing);
  }
  // Every photo black, of the camera's size.
  void Blacken() const {
    for (const auto& e : fs::directory_iterator(photo))
      ASSERT_TRUE(cv::imwrite(e.path().string(), cv::Mat(520, 696, CV_8U, cv::Scalar(0))));
  }
};

// Navigation positions by image, as the simulation wrote them.
std::map<std::string, std::pair<double, double>> NavPositions(const std::string& nav) {
  std::map<std::string, std::pair<double, double>> out;
  const auto lines = Lines(nav);
  for (size_t i = 1; i < lines.size(); ++i) {
    const auto f = Split(lines[i]);
    out[f[0]] = {std::stod(f[2]), std::stod(f[3])};
  }
  return out;
}

bool Has(const std::string& log, const std::string& part) {
  return log.find(part) != std::string::npos;
}

// Row 9: refine and visual odometry read photos through the build's header
// check, with the build's limit (config max_image_pixels).
TEST(HostileInputs, RefineHonoursTheConfiguredImageLimitBeforeDecoding) {
  Copy c;
  testing::WriteBytes(c.Image(3), testing::ZeroPng(2000, 1500));  // 3 Mpx, valid
  std::ofstream(c.Path("config.json")) << R"({"max_image_pixels": 1000000})";
  std::string log;
  ASSERT_EQ(c.Trajectory("refine", &log, "--config " + c.Path("config.json")), 0) << log;
  EXPECT_TRUE(
      Has(log, "frame_000003.png: image too large: its header says 2000x1500 pixels, over the limit of 1000000"))
      << log;
  EXPECT_TRUE(Has(c.Rows()["frame_000003.png"]["flags"], "no_image")) << log;
}

TEST(HostileInputs, BuildRefineNavRefusesHugePngHeadersUnread) {
  Copy c;
  testing::WriteBytes(c.Image(3), testing::ZeroPng(30000, 30000));  // 875 KB each
  testing::WriteBytes(c.Image(5), testing::ZeroPng(30000, 30000));
  std::string log;
  ASSERT_EQ(
      Seamap("build --refine-nav" + c.Inputs() + " --out " + c.Path("m.mbtiles") + " --report " + c.Path("report.json"),
             &log),
      0)
      << log;
  EXPECT_TRUE(Has(log, "refine: frame_000003.png: image too large: its header says 30000x30000")) << log;
  EXPECT_TRUE(Has(log, "refine: frame_000005.png: image too large")) << log;
  std::ifstream report(c.Path("report.json"));
  EXPECT_LT(nlohmann::json::parse(report).at("peak_rss_bytes").get<int64_t>(), kMemoryLimitBytes);
}

TEST(HostileInputs, VisualOdometryFlagsHugeAndBlackPhotos) {
  Copy c;
  testing::WriteBytes(c.Image(4), testing::ZeroPng(30000, 30000));
  std::string log;
  ASSERT_EQ(c.Trajectory("vo", &log), 0) << log;
  auto rows = c.Rows();
  EXPECT_EQ(rows["frame_000004.png"]["flags"], "no_image") << log;
  EXPECT_EQ(rows["frame_000005.png"]["flags"], "");

  // All black: every frame flagged, none measured (it drifted 5.4 m silently).
  c.Blacken();
  ASSERT_EQ(c.Trajectory("vo", &log), 0) << log;
  rows = c.Rows();
  ASSERT_EQ(rows.size(), 24u);
  for (const auto& [image, row] : rows) EXPECT_TRUE(Has(row.at("flags"), "low_texture")) << image << "\n" << log;
}

// Row 10: declared counts against the file's size; no /dev/zero.
TEST(HostileInputs, GeorefRefusesCloudsThatDeclareMoreThanTheyHoldAndNonFiles) {
  testing::TempDir dir;
  std::string log;
  const std::string survey = (dir.path() / "buoy").string();
  ASSERT_EQ(Seamap("simulate-buoy --out " + survey + " --force --cloud-points 50", &log), 0) << log;
  const std::string ply = (dir.path() / "big.ply").string();
  std::ofstream(ply) << "ply\nformat binary_little_endian 1.0\nelement vertex 150000000\nproperty float x\n"
                        "property float y\nproperty float z\nend_header\n";
  const std::string georef = "georef --buoy " + survey + "/buoy.csv --tether-length 30 --depth-csv " + survey +
                             "/depth.csv --out " + (dir.path() / "nav.csv").string();
  EXPECT_EQ(Seamap(georef + " --keyframes " + survey + "/keyframes.txt --points " + ply + " --points-out " +
                       (dir.path() / "out.ply").string(),
                   &log),
            2)
      << log;
  EXPECT_TRUE(Has(log, ply + ":3: field 'vertex': declares 150000000 vertices, but the 0 bytes")) << log;
  EXPECT_EQ(Seamap(georef + " --keyframes /dev/zero", &log), 2) << log;
  EXPECT_TRUE(Has(log, "/dev/zero: cannot read the keyframe file: not a regular file (a character device)")) << log;
}

// Row 11: a jump in the navigation's time restarts the filter there.
TEST(HostileInputs, FilterRestartsAcrossAJumpInTime) {
  for (const std::string& jump : {std::string("1e8"), std::string("31557600")}) {
    Copy c;
    auto lines = Lines(c.nav);
    for (size_t i = 13; i < lines.size(); ++i) {  // from frame 12 on
      auto f = Split(lines[i]);
      std::ostringstream t;
      t << std::setprecision(17) << std::stod(f[1]) + std::stod(jump);
      f[1] = t.str();
      lines[i].clear();
      for (const auto& v : f) lines[i] += (lines[i].empty() ? "" : ",") + v;
    }
    std::ofstream out(c.nav, std::ios::trunc);
    for (const auto& l : lines) out << l << "\n";
    out.close();
    for (const std::string mode : {"ekf", "vo"}) {
      std::string log;
      ASSERT_EQ(c.Trajectory(mode, &log, "--report " + c.Path("report.json")), 0) << log;
      EXPECT_TRUE(Has(log, mode + ": the navigation's time jumps by")) << log;
      EXPECT_TRUE(Has(log, "the filter restarted there from the navigation")) << log;
      const auto rows = c.Rows();
      for (const auto& [image, row] : rows)
        EXPECT_EQ(Has(row.at("flags"), "restart_after_gap"), image == "frame_000012.png") << image;
      std::ifstream report(c.Path("report.json"));
      EXPECT_EQ(nlohmann::json::parse(report).at("restarts_after_gap").size(), 1u);
    }
  }
}

// Row 13: a frozen camera or black photos correct nothing, and say so.
TEST(HostileInputs, RefineOnAFrozenCameraCorrectsNothingAndSaysSo) {
  Copy c;
  c.FreezeCamera();
  std::string log;
  ASSERT_EQ(c.Trajectory("refine", &log), 0) << log;
  EXPECT_TRUE(Has(log, "frames are the same photo as a neighbour")) << log;
  EXPECT_TRUE(Has(log, "refine: poses corrected in 0 of 24 frames")) << log;
  const auto nav = NavPositions(c.nav);
  for (const auto& [image, row] : c.Rows()) {
    EXPECT_NEAR(std::stod(row.at("x_m")), nav.at(image).first, 1e-5) << image;
    EXPECT_NEAR(std::stod(row.at("y_m")), nav.at(image).second, 1e-5) << image;
    EXPECT_TRUE(Has(row.at("flags"), "identical_photos")) << image;
  }
  // Visual odometry measures nothing from them and says so.
  ASSERT_EQ(c.Trajectory("vo", &log), 0) << log;
  const auto rows = c.Rows();
  for (int i = 1; i < 24; ++i) {
    std::ostringstream image;
    image << "frame_" << std::setw(6) << std::setfill('0') << i << ".png";
    EXPECT_TRUE(Has(rows.at(image.str()).at("flags"), "identical_photos")) << image.str();
  }
  // The map says the trajectory was not corrected.
  ASSERT_EQ(Seamap("build --refine-nav" + c.Inputs() + " --out " + c.Path("m.mbtiles"), &log), 0) << log;
  ASSERT_EQ(Seamap("info " + c.Path("m.mbtiles"), &log), 0) << log;
  EXPECT_TRUE(Has(log, "trajectory not corrected")) << log;
  EXPECT_TRUE(Has(log, "flagged:   identical_photos 24")) << log;
}

TEST(HostileInputs, RefineOnBlackPhotosNamesTheCause) {
  Copy c;
  c.Blacken();
  std::string log;
  ASSERT_EQ(c.Trajectory("refine", &log), 0) << log;
  EXPECT_TRUE(Has(log, "no texture: the image is uniform")) << log;
  EXPECT_TRUE(Has(log, "refine: poses corrected in 0 of 24 frames")) << log;
  for (const auto& [image, row] : c.Rows()) EXPECT_EQ(row.at("flags"), "nav_only;no_texture") << image;
}

// Row 14: georef-eval refuses what no survey holds.
TEST(HostileInputs, GeorefEvalRefusesHugeValuesAndEmptyFiles) {
  testing::TempDir dir;
  const std::string truth = (dir.path() / "truth").string();
  fs::create_directories(truth);
  std::ofstream(truth + "/truth.json") << R"({"origin": {"lat": 43.1, "lon": 131.9}})";
  std::ofstream(truth + "/truth.csv") << "time_s,x_m,y_m,depth_m,heading_deg\n0,1,2,30,10\n1,1.5,2,30,10\n";
  const std::string nav = (dir.path() / "nav.csv").string();
  const std::string header = "time_s,lat,lon,depth_m,heading_deg,good\n";
  std::string log;
  std::ofstream(nav) << header << "0,43.1,131.9,30,10,1\n1,1e308,131.9,30,10,1\n";
  EXPECT_EQ(Seamap("georef-eval --nav " + nav + " --truth " + truth, &log), 2) << log;
  EXPECT_TRUE(Has(log, nav + ": field 'lat': row 2: 1e+308 is out of range, expected -90 to 90")) << log;
  std::ofstream(nav, std::ios::trunc) << header << "0,43.1,131.9,1e308,10,1\n";
  EXPECT_EQ(Seamap("georef-eval --nav " + nav + " --truth " + truth, &log), 2) << log;
  EXPECT_TRUE(Has(log, "field 'depth_m'")) << log;
  EXPECT_FALSE(Has(log, "inf")) << log;
  std::ofstream(nav, std::ios::trunc) << header;
  EXPECT_EQ(Seamap("georef-eval --nav " + nav + " --truth " + truth, &log), 2) << log;
  EXPECT_TRUE(Has(log, "no keyframes")) << log;
}

}  // namespace
}  // namespace seamap
