// `seamap trajectory --mode vo --buoy` (issue 30, part 4): SeaMap's own
// trajectory, without absolute fixes, put on the Earth with a towed buoy's GPS
// (seed 002's method). The survey's navigation is moved 36 m (no fix to trust)
// and drifts; the buoy is towed on a 4 m tether along the true path
// (core/georef/tether_model.h) with noisy fixes. The result is compared with
// `seamap georef` on the same fixes given exact keyframes (the truth).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/georef/tether.h"
#include "core/georef/tether_model.h"
#include "core/georef/tum_trajectory.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;

constexpr double kTetherM = 4.0;
constexpr double kGpsSigmaM = 0.4;  // per axis, 1 Hz

// 160 frames over 8 m lines in 5 m of water (the vehicle ~3.2 m deep: a 4 m tether pulls taut along a line).
const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("buoy_vo",
                               "--frames 160 --line-length 8 --line-spacing 0.9 --sea-depth 5 --nav-drift 0.5 "
                               "--nav-noise 0.005 --heading-noise 0.5 --image-format jpg --seed 6 --quiet");
}

struct Row {
  std::map<std::string, std::string> cells;
  double Get(const std::string& c) const { return std::stod(cells.at(c)); }
};

std::vector<Row> ReadCsv(const std::string& path, std::string* header = nullptr) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  if (header) *header = line;
  std::vector<std::string> names;
  std::stringstream h(line);
  for (std::string c; std::getline(h, c, ',');) names.push_back(c);
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    Row r;
    std::stringstream s(line);
    std::string c;
    for (size_t k = 0; k < names.size() && std::getline(s, c, ','); ++k) r.cells[names[k]] = c;
    rows.push_back(r);
  }
  return rows;
}

struct Scene {
  std::unique_ptr<testing::TempDir> dir;
  std::string moved_nav, buoy, depth, truth_tum;
  std::vector<Row> truth;
};

// The moved navigation, the buoy's fixes and the truth as exact keyframes, once per test binary.
const Scene& SharedScene() {
  static Scene scene = [] {
    Scene s;
    s.dir = std::make_unique<testing::TempDir>();
    const auto& survey = Survey();
    s.truth = ReadCsv(survey.dir + "/nav_truth.csv");
    // No absolute fix: every position of the navigation 30 m east and 20 m south of the truth.
    std::string header;
    const std::vector<Row> nav = ReadCsv(survey.nav, &header);
    s.moved_nav = (s.dir->path() / "moved_nav.csv").string();
    {
      std::ofstream o(s.moved_nav);
      o << header << "\n";
      std::vector<std::string> names;
      std::stringstream h(header);
      for (std::string c; std::getline(h, c, ',');) names.push_back(c);
      for (const Row& r : nav) {
        for (size_t k = 0; k < names.size(); ++k) {
          std::string v = r.cells.at(names[k]);
          if (names[k] == "x_m") v = std::to_string(r.Get("x_m") + 30);
          if (names[k] == "y_m") v = std::to_string(r.Get("y_m") - 20);
          o << (k ? "," : "") << v;
        }
        o << "\n";
      }
    }
    // The buoy towed along the true path (linear between frames, 20 ms steps), starting astern.
    const LocalFrame frame({43.1, 131.9});
    const Row& first = s.truth.front();
    const double heading0 = first.Get("heading_deg") * M_PI / 180;
    const double reach0 = TetherReach(kTetherM, first.Get("depth_m"));
    TowedBuoy buoy(Eigen::Vector2d(first.Get("x_m") - reach0 * std::sin(heading0),
                                   first.Get("y_m") - reach0 * std::cos(heading0)));
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0, kGpsSigmaM);
    s.buoy = (s.dir->path() / "buoy.csv").string();
    s.depth = (s.dir->path() / "depth.csv").string();
    std::ofstream fixes(s.buoy), depth(s.depth);
    fixes << "time_s,lat,lon\n";
    depth << "time_s,depth_m\n";
    double next_fix_s = 0;
    for (size_t i = 0; i + 1 < s.truth.size(); ++i) {
      const Row &a = s.truth[i], &b = s.truth[i + 1];
      depth << a.cells.at("time_s") << "," << a.cells.at("depth_m") << "\n";
      const double t0 = a.Get("time_s"), t1 = b.Get("time_s");
      for (double t = t0; t < t1 - 1e-9; t += 0.02) {
        const double f = (t - t0) / (t1 - t0);
        const Eigen::Vector2d at((1 - f) * a.Get("x_m") + f * b.Get("x_m"), (1 - f) * a.Get("y_m") + f * b.Get("y_m"));
        buoy.Step(at, TetherReach(kTetherM, (1 - f) * a.Get("depth_m") + f * b.Get("depth_m")));
        if (t >= next_fix_s - 1e-9) {
          const LatLon ll = frame.ToLatLon({buoy.position().x() + noise(rng), buoy.position().y() + noise(rng)});
          char line[96];
          std::snprintf(line, sizeof line, "%.3f,%.10f,%.10f\n", t, ll.lat, ll.lon);
          fixes << line;
          next_fix_s += 1.0;
        }
      }
    }
    // Exact keyframes: the true positions in a frame of their own (the fit finds the similarity).
    std::vector<Keyframe> keyframes;
    for (const Row& r : s.truth) {
      Keyframe k;
      k.time_s = r.Get("time_s");
      k.position_slam = Eigen::Vector3d(r.Get("x_m"), r.Get("y_m"), -r.Get("depth_m"));
      k.world_from_cam = Eigen::Quaterniond::Identity();
      keyframes.push_back(k);
    }
    s.truth_tum = (s.dir->path() / "truth.tum").string();
    WriteTumTrajectory(s.truth_tum, keyframes);
    return s;
  }();
  return scene;
}

// Horizontal RMS error of positions (local metres about the survey's origin) against the truth, by time.
double HorizontalRmse(const std::map<double, Eigen::Vector2d>& estimate, const std::vector<Row>& truth) {
  double sum2 = 0;
  int n = 0;
  for (const Row& r : truth) {
    const auto e = estimate.lower_bound(r.Get("time_s") - 1e-4);
    if (e == estimate.end() || std::abs(e->first - r.Get("time_s")) > 1e-3) continue;
    sum2 += (e->second - Eigen::Vector2d(r.Get("x_m"), r.Get("y_m"))).squaredNorm();
    ++n;
  }
  EXPECT_EQ(n, static_cast<int>(truth.size()));
  return n ? std::sqrt(sum2 / n) : INFINITY;
}

std::string TrajectoryArgs(const Scene& s) {
  const auto& survey = Survey();
  return "trajectory --images " + survey.photo + " --nav " + s.moved_nav + " --camera " + survey.camera + " --origin " +
         survey.origin + " --nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5 --quiet";
}

TEST(TrajectoryBuoy, VisualOdometryIsPutOnTheEarthAsWellAsExactKeyframesAre) {
  const Scene& s = SharedScene();
  testing::TempDir dir;
  const std::string out = (dir / "vo_earth.csv").string();
  std::string log;
  ASSERT_EQ(Seamap(TrajectoryArgs(s) + " --mode vo --out " + out + " --buoy " + s.buoy + " --tether-length " +
                       std::to_string(kTetherM),
                   &log),
            0)
      << log;
  std::printf("%s", log.c_str());
  EXPECT_NE(log.find("trajectory (vo, buoy-georeferenced): 160 frames -> " + out), std::string::npos) << log;
  // The report beside the trajectory: the fit's figures.
  const std::string report_path = (dir / "vo_earth.georef.json").string();
  std::ifstream report_file(report_path);
  ASSERT_TRUE(report_file.good()) << report_path;
  const nlohmann::json report = nlohmann::json::parse(report_file);
  ASSERT_TRUE(report.contains("predicted_rmse_m")) << report.dump().substr(0, 400);
  const double predicted = report["predicted_rmse_m"].get<double>();

  const LocalFrame frame({43.1, 131.9});
  std::map<double, Eigen::Vector2d> vo;
  for (const Row& r : ReadCsv(out)) {
    // x_m, y_m in the survey's frame agree with lat, lon.
    const LocalXY xy = frame.FromLatLon({r.Get("lat"), r.Get("lon")});
    EXPECT_NEAR(xy.east, r.Get("x_m"), 1e-3);
    EXPECT_NEAR(xy.north, r.Get("y_m"), 1e-3);
    vo[r.Get("time_s")] = {r.Get("x_m"), r.Get("y_m")};
  }
  const double vo_rmse = HorizontalRmse(vo, s.truth);

  // The reference: georef on the same fixes with the exact keyframes.
  const std::string ref = (dir / "ref_nav.csv").string();
  ASSERT_EQ(Seamap("georef --keyframes " + s.truth_tum + " --buoy " + s.buoy + " --tether-length " +
                       std::to_string(kTetherM) + " --depth-csv " + s.depth + " --out " + ref + " --quiet",
                   &log),
            0)
      << log;
  std::map<double, Eigen::Vector2d> exact;
  for (const Row& r : ReadCsv(ref)) {
    const LocalXY xy = frame.FromLatLon({r.Get("lat"), r.Get("lon")});
    exact[r.Get("time_s")] = {xy.east, xy.north};
  }
  const double exact_rmse = HorizontalRmse(exact, s.truth);
  std::printf("vo + buoy: horizontal RMSE %.3f m (predicted %.3f m); georef with exact keyframes %.3f m\n", vo_rmse,
              predicted, exact_rmse);
  // The navigation was 36 m off; the buoy puts the trajectory about as near the truth as exact
  // keyframes get (the target: 1.5x; here 0.152 against 0.149 m) plus VO's own shape error
  // (its drift, under 1 % of the 20 m path: scripts/bench_dive_buoy.sh measures 1.4-2.1x on other
  // draws, where the exact fit is 6-9 cm), and within twice what the fit predicts.
  EXPECT_LT(vo_rmse, 1.5 * exact_rmse + 0.05);
  EXPECT_LT(vo_rmse, 2 * predicted);
  // The trajectory is metric: the fitted scale is ~1.
  ASSERT_TRUE(report.contains("scale")) << report.dump().substr(0, 400);
  EXPECT_NEAR(report["scale"].get<double>(), 1.0, 0.05);
}

TEST(TrajectoryBuoy, BuoyOptionsThatDoNotFitAreRefusedBeforeThePhotosAreRead) {
  const Scene& s = SharedScene();
  testing::TempDir dir;
  const std::string out = (dir / "t.csv").string();
  std::string log;
  EXPECT_EQ(Seamap(TrajectoryArgs(s) + " --mode ekf --out " + out + " --buoy " + s.buoy + " --tether-length 4", &log),
            2);
  EXPECT_NE(log.find("--buoy"), std::string::npos) << log;
  EXPECT_EQ(Seamap(TrajectoryArgs(s) + " --mode vo --out " + out + " --tether-length 4", &log), 2);
  EXPECT_NE(log.find("--tether-length: goes with --buoy"), std::string::npos) << log;
  EXPECT_EQ(Seamap(TrajectoryArgs(s) + " --mode vo --out " + out + " --buoy " + s.buoy, &log), 2);
  EXPECT_NE(log.find("--tether-length"), std::string::npos) << log;
  EXPECT_EQ(Seamap(TrajectoryArgs(s) + " --mode vo --out " + out + " --buoy " + s.buoy + " --tether-length 4" +
                       " --buoy-method best",
                   &log),
            2);
  EXPECT_NE(log.find("--buoy-method"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace seamap
