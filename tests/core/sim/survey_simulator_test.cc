#include "core/sim/survey_simulator.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/camera/camera_model.h"
#include "core/sim/ground_truth.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {
namespace fs = std::filesystem;

const char* kHeader = "image,time_s,x_m,y_m,altitude_m,depth_m,heading_deg,pitch_deg,roll_deg";

SimulationOptions SmallSurvey(const fs::path& out) {
  SimulationOptions o;
  o.out_dir = out.string();
  o.camera = CameraFromFocalLength(8.0, 12.9 * 696 / 160, 160, 120);
  o.trajectory.frames = 8;
  o.seed = 42;
  return o;
}

std::vector<std::string> Lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string Bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SurveySimulatorTest, DefaultsReproduceTheSeedExperiment) {
  const SimulationOptions o;
  EXPECT_EQ(o.camera.width, 696);
  EXPECT_EQ(o.camera.height, 520);
  EXPECT_NEAR(o.camera.fx, 620.155, 1e-3);  // 8 mm / 12.9 um
  EXPECT_EQ(o.camera.distortion[0], -0.05);
  EXPECT_EQ(o.trajectory.fps, 5);
  EXPECT_EQ(o.trajectory.frames, 400);
  EXPECT_EQ(o.trajectory.altitude_min_m, 1.6);
  EXPECT_EQ(o.trajectory.altitude_max_m, 2.0);
  EXPECT_FALSE(o.color);
  EXPECT_EQ(o.bit_depth, 8);
  EXPECT_FALSE(o.degradations.Any());
  EXPECT_EQ(o.nav_errors.position_sigma_m, 0);
  EXPECT_EQ(o.nav_errors.heading_sigma_deg, 0);
  EXPECT_EQ(o.nav_errors.drift_m_per_min, 0);
}

TEST(SurveySimulatorTest, WritesTheLayout) {
  testing::TempDir dir;
  const fs::path out = dir / "survey";
  int last_progress = 0;
  const SimulationSummary s = SimulateSurvey(SmallSurvey(out), [&](int done, int total) {
    last_progress = done;
    EXPECT_EQ(total, 8);
  });
  EXPECT_EQ(s.frames, 8);
  EXPECT_EQ(last_progress, 8);
  EXPECT_GT(s.area_m2, 1);
  for (int i = 0; i < 8; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", i);
    const cv::Mat frame = cv::imread((out / "photo" / name).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(frame.type(), CV_8UC1) << name;
    EXPECT_EQ(frame.size(), cv::Size(160, 120));
    EXPECT_EQ(cv::countNonZero(frame == 0), 0) << "texture covers every footprint";
  }
  const auto nav = Lines(out / "nav.csv"), truth = Lines(out / "nav_truth.csv");
  ASSERT_EQ(nav.size(), 9u);
  EXPECT_EQ(nav[0], kHeader);
  EXPECT_EQ(truth[0], kHeader);
  EXPECT_EQ(nav, truth);  // no navigation errors asked for
  EXPECT_EQ(nav[1].rfind("frame_000000.png,0.000000,0.000000,0.000000,", 0), 0u) << nav[1];

  const CameraModel cam = LoadCamera((out / "camera.json").string());
  EXPECT_EQ(cam.width, 160);
  EXPECT_NEAR(cam.fx, 8000 / (12.9 * 696 / 160), 1e-9);

  const GroundTruth g = GroundTruth::Load(out.string());
  EXPECT_EQ(g.image.size(), s.texture_size);
  EXPECT_EQ(g.origin.lat, 43.1);

  std::ifstream json_in(out / "survey.json");
  const auto j = nlohmann::json::parse(json_in);
  EXPECT_EQ(j["seed"], 42);
  EXPECT_EQ(j["frames"], 8);
  EXPECT_EQ(j["origin"][1], 131.9);
  EXPECT_EQ(j["path"]["type"], "lawnmower");
}

TEST(SurveySimulatorTest, FramesShowTheTruthUnderTheTruePose) {
  testing::TempDir dir;
  SimulationOptions o = SmallSurvey(dir / "s");
  o.trajectory.pitch_amp_deg = o.trajectory.roll_amp_deg = 0;
  o.camera.distortion = {};
  SimulateSurvey(o);
  const GroundTruth g = GroundTruth::Load(o.out_dir);
  const auto line = Lines(dir / "s" / "nav_truth.csv")[4];  // frame 3
  double t, x, y, alt, depth, heading;
  ASSERT_EQ(std::sscanf(line.c_str(), "frame_000003.png,%lf,%lf,%lf,%lf,%lf,%lf", &t, &x, &y, &alt, &depth, &heading),
            6);
  EXPECT_NEAR(heading, 0, 1e-6);
  const cv::Mat frame = cv::imread((dir / "s" / "photo" / "frame_000003.png").string(), cv::IMREAD_UNCHANGED);
  const CameraModel& c = o.camera;
  for (auto [u, v] : {std::pair{c.cx, c.cy}, std::pair{c.cx + 40.5, c.cy - 30.5}}) {
    cv::Vec3f truth;
    ASSERT_TRUE(g.Sample({x + (u - c.cx) / c.fx * alt, y - (v - c.cy) / c.fy * alt}, &truth));
    // The pixel nearest (u, v) is within half a pixel: compare with its 2x2 neighbourhood mean.
    const cv::Rect box(static_cast<int>(u), static_cast<int>(v), 2, 2);
    EXPECT_NEAR(cv::mean(frame(box))[0], truth[0], 12) << u << "," << v;
  }
}

TEST(SurveySimulatorTest, SameSeedSameSurvey) {
  testing::TempDir dir;
  SimulationOptions a = SmallSurvey(dir / "a"), b = SmallSurvey(dir / "b"), c = SmallSurvey(dir / "c");
  a.degradations = b.degradations = c.degradations = Degradations::Moderate();
  c.seed = 43;
  SimulateSurvey(a);
  SimulateSurvey(b);
  SimulateSurvey(c);
  for (const char* file : {"photo/frame_000005.png", "nav.csv", "truth/texture.png"})
    EXPECT_EQ(Bytes(dir / "a" / file), Bytes(dir / "b" / file)) << file;
  EXPECT_NE(Bytes(dir / "a" / "photo/frame_000005.png"), Bytes(dir / "c" / "photo/frame_000005.png"));
}

TEST(SurveySimulatorTest, RefusesANonEmptyFolderUnlessForced) {
  testing::TempDir dir;
  SimulationOptions o = SmallSurvey(dir / "s");
  testing::WriteFile(dir / "s" / "keep.txt", "mine");
  try {
    SimulateSurvey(o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--out");
  }
  o.force = true;
  o.trajectory.frames = 3;
  testing::WriteFile(dir / "s" / "photo" / "frame_000009.png", "stale");
  EXPECT_EQ(SimulateSurvey(o).frames, 3);
  EXPECT_TRUE(fs::exists(dir / "s" / "keep.txt"));  // not ours: left alone
  EXPECT_FALSE(fs::exists(dir / "s" / "photo" / "frame_000009.png"));
  EXPECT_EQ(Lines(dir / "s" / "nav.csv").size(), 4u);
}

TEST(SurveySimulatorTest, NavigationErrorsOnlyInNavCsv) {
  testing::TempDir dir;
  SimulationOptions o = SmallSurvey(dir / "s");
  o.nav_errors.position_sigma_m = 0.05;
  o.nav_errors.drift_m_per_min = 1;
  SimulateSurvey(o);
  const auto nav = Lines(dir / "s" / "nav.csv"), truth = Lines(dir / "s" / "nav_truth.csv");
  ASSERT_EQ(nav.size(), truth.size());
  EXPECT_NE(nav[3], truth[3]);
  double xn, xt;
  std::sscanf(nav[3].c_str(), "frame_000002.png,%*f,%lf", &xn);
  std::sscanf(truth[3].c_str(), "frame_000002.png,%*f,%lf", &xt);
  EXPECT_NE(xn, xt);
  EXPECT_LT(std::fabs(xn - xt), 0.5);
}

TEST(SurveySimulatorTest, SixteenBitColourAndJpegOutputs) {
  testing::TempDir dir;
  SimulationOptions o = SmallSurvey(dir / "deep");
  o.trajectory.frames = 2;
  o.bit_depth = 16;
  o.color = true;
  SimulateSurvey(o);
  const cv::Mat deep = cv::imread((dir / "deep" / "photo" / "frame_000001.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(deep.type(), CV_16UC3);
  EXPECT_EQ(GroundTruth::Load(o.out_dir).image.type(), CV_16UC3);

  SimulationOptions j = SmallSurvey(dir / "jpg");
  j.trajectory.frames = 2;
  j.image_format = "jpg";
  SimulateSurvey(j);
  EXPECT_TRUE(fs::exists(dir / "jpg" / "photo" / "frame_000001.jpg"));
  EXPECT_EQ(Lines(dir / "jpg" / "nav.csv")[2].rfind("frame_000001.jpg,", 0), 0u);

  j.bit_depth = 16;
  j.out_dir = (dir / "bad").string();
  try {
    SimulateSurvey(j);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--bit-depth");
  }
}

TEST(SurveySimulatorTest, CustomPathAndTooSmallTexture) {
  testing::TempDir dir;
  SimulationOptions o = SmallSurvey(dir / "s");
  o.path_file = testing::WriteFile(dir / "path.csv", "x_m,y_m\n0,0\n0.5,0\n").string();
  o.trajectory.frames = 50;
  EXPECT_EQ(SimulateSurvey(o).frames, 6);  // 0.5 m at 0.1 m per frame
  EXPECT_NEAR(std::stod(Lines(dir / "s" / "nav_truth.csv")[6].substr(std::string("frame_000005.png,").size() + 9)), 0.5,
              1e-6);

  cv::imwrite((dir / "small.png").string(), cv::Mat(10, 10, CV_8UC1, cv::Scalar(100)));
  SimulationOptions t = SmallSurvey(dir / "t");
  t.texture_file = (dir / "small.png").string();
  t.texture_res_m = 0.01;
  try {
    SimulateSurvey(t);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--texture");
  }
  t.texture_res_m = 1.0;  // 10 m square: enough
  EXPECT_EQ(SimulateSurvey(t).frames, 8);
}

}  // namespace
}  // namespace seamap
