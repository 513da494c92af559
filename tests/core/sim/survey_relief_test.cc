// `seamap simulate --relief`: the vehicle over a rugged seabed, the DVL's
// altitude, truth/terrain.tif and GroundTruth's heights.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "core/geo/rotation.h"
#include "core/sim/ground_truth.h"
#include "core/sim/survey_simulator.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {
namespace fs = std::filesystem;

SimulationOptions ReliefSurvey(const fs::path& out, double relief_m) {
  SimulationOptions o;
  o.out_dir = out.string();
  o.camera = CameraFromFocalLength(8.0, 12.9 * 696 / 160, 160, 120);
  o.trajectory.frames = 10;
  o.trajectory.altitude_min_m = o.trajectory.altitude_max_m = 2;
  o.seed = 5;
  o.relief.rms_m = relief_m;
  return o;
}

std::vector<VehiclePose> ReadPoses(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<VehiclePose> poses;
  while (std::getline(in, line)) {
    VehiclePose p;
    double t = 0;
    const size_t comma = line.find(',');
    EXPECT_EQ(std::sscanf(line.c_str() + comma + 1, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &t, &p.east_m, &p.north_m,
                          &p.altitude_m, &p.depth_m, &p.heading_deg, &p.pitch_deg, &p.roll_deg),
              8);
    poses.push_back(p);
  }
  return poses;
}

// The DVL's altitude by brute force: each beam marched in 1 mm steps over
// the truth's bilinear heights, the crossing interpolated.
double BruteForceDvl(const GroundTruth& truth, const VehiclePose& p) {
  const Eigen::Matrix3d ned_from_body = NedFromBodyDeg(p.heading_deg, p.pitch_deg, p.roll_deg);
  double sum = 0;
  for (int k = 0; k < 4; ++k) {
    const double az = (45 + 90 * k) * M_PI / 180, tilt = M_PI / 6;
    const Eigen::Vector3d ned =
        ned_from_body * Eigen::Vector3d(std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az), std::cos(tilt));
    double previous_gap = INFINITY;
    for (double s = 0; s < 10; s += 0.001) {
      const double up = -p.depth_m - s * ned.z();
      double ground = 0;
      if (!truth.SeabedHeight({p.east_m + s * ned.y(), p.north_m + s * ned.x()}, &ground)) return NAN;
      const double gap = up - ground;
      if (gap <= 0) {
        const double s_hit = s - 0.001 * gap / (gap - previous_gap);
        sum += s_hit * ned.z();
        break;
      }
      previous_gap = gap;
    }
  }
  return sum / 4;
}

TEST(SurveyReliefTest, TheVehicleKeepsItsDepthAndTheDvlMeasuresTheRangeBelow) {
  testing::TempDir dir;
  const SimulationOptions o = ReliefSurvey(dir / "relief", 0.2);
  const SimulationSummary s = SimulateSurvey(o);
  EXPECT_GT(s.min_clearance_m, 1);
  SimulationOptions flat_options = ReliefSurvey(dir / "flat", 0);
  SimulateSurvey(flat_options);
  EXPECT_FALSE(fs::exists(dir / "flat" / "truth" / "terrain.tif"));
  EXPECT_TRUE(GroundTruth::Load(flat_options.out_dir).terrain.empty());

  const GroundTruth truth = GroundTruth::Load(o.out_dir);
  ASSERT_FALSE(truth.terrain.empty());
  const std::vector<VehiclePose> poses = ReadPoses(dir / "relief" / "nav_truth.csv");
  const std::vector<VehiclePose> reported = ReadPoses(dir / "relief" / "nav.csv");
  const std::vector<VehiclePose> flat = ReadPoses(dir / "flat" / "nav_truth.csv");
  ASSERT_EQ(poses.size(), 10u);
  ASSERT_EQ(flat.size(), 10u);
  double largest_change = 0;
  for (size_t i = 0; i < poses.size(); ++i) {
    EXPECT_NEAR(poses[i].depth_m, flat[i].depth_m, 1e-6);  // the same depth as over the flat seabed
    EXPECT_NEAR(poses[i].east_m, flat[i].east_m, 1e-6);
    EXPECT_NEAR(reported[i].altitude_m, poses[i].altitude_m, 1e-6);
    EXPECT_NEAR(poses[i].altitude_m, BruteForceDvl(truth, poses[i]), 1e-3) << "frame " << i;
    largest_change = std::max(largest_change, std::fabs(poses[i].altitude_m - flat[i].altitude_m));
  }
  EXPECT_GT(largest_change, 0.02);  // the relief shows in the altitude
}

TEST(SurveyReliefTest, TerrainTifHoldsTheTrueHeightsOverTheTexture) {
  testing::TempDir dir;
  const SimulationOptions o = ReliefSurvey(dir / "s", 0.15);
  SimulateSurvey(o);
  const GroundTruth truth = GroundTruth::Load(o.out_dir);
  const HeightGrid& t = truth.terrain;
  ASSERT_FALSE(t.empty());
  EXPECT_TRUE(t.has_depth_datum);
  EXPECT_NEAR(cv::mean(t.height_m)[0], -o.trajectory.sea_depth_m, 1e-3);
  cv::Scalar mean, stddev;
  cv::meanStdDev(t.height_m, mean, stddev);
  EXPECT_NEAR(stddev[0], 0.15, 1e-3);
  // The same extent as the texture.
  EXPECT_NEAR(t.east0_m - t.cell_m / 2, truth.east_min, 1e-6);
  EXPECT_NEAR(t.north0_m + t.cell_m / 2, truth.north_max, 1e-6);
  EXPECT_NEAR(t.cols() * t.cell_m, truth.image.cols * truth.res_m, t.cell_m);
  double up = 0;
  EXPECT_TRUE(truth.SeabedHeight({0, 0}, &up));
  EXPECT_NEAR(up, -35, 1);
  std::ifstream in(dir / "s" / "survey.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["relief_m"], 0.15);
  EXPECT_EQ(j["relief"]["source"], "random");
}

TEST(SurveyReliefTest, ReliefReachingTheVehicleIsRefused) {
  testing::TempDir dir;
  SimulationOptions o = ReliefSurvey(dir / "s", 0.6);
  o.trajectory.altitude_min_m = o.trajectory.altitude_max_m = 1.0;
  try {
    SimulateSurvey(o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--relief");
    EXPECT_NE(std::string(e.what()).find("--altitude-min"), std::string::npos);
  }
}

}  // namespace
}  // namespace seamap
