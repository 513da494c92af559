#include "core/controllers/trajectory_georef.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "core/georef/tether.h"
#include "core/georef/tether_model.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

constexpr double kDeg = M_PI / 180;

// A trajectory without absolute fixes: the truth (a lawnmower of three 30 m lines, 1 Hz, 3 m deep)
// turned 10 degrees and moved (50, -30) m, as visual odometry started at a wrong fix and heading
// would give it; and a buoy towed along the truth on a 5 m tether, fixes with 0.1 m of noise.
struct Scene {
  testing::TempDir dir;
  std::vector<TrajectoryRow> truth, estimate;
  std::string buoy;
};

void Make(Scene* s) {
  const LocalFrame frame({43.1, 131.9});
  std::vector<Eigen::Vector2d> corners = {{0, 0}, {0, 30}, {10, 30}, {10, 0}, {20, 0}, {20, 30}};
  double t = 0;
  for (size_t k = 0; k + 1 < corners.size(); ++k) {
    const Eigen::Vector2d a = corners[k], b = corners[k + 1];
    const double heading = std::fmod(std::atan2(b.x() - a.x(), b.y() - a.y()) / kDeg + 360, 360.0);
    for (double s_m = 0; s_m < (b - a).norm() - 1e-9; s_m += 0.5, t += 1) {
      const Eigen::Vector2d p = a + s_m * (b - a).normalized();
      TrajectoryRow row;
      row.image = "f" + std::to_string(s->truth.size()) + ".png";
      row.time_s = t;
      row.pose.east_m = p.x(), row.pose.north_m = p.y(), row.pose.depth_m = 3, row.pose.altitude_m = 2;
      row.pose.heading_deg = heading;
      s->truth.push_back(row);
      TrajectoryRow moved = row;
      const double c = std::cos(10 * kDeg), sn = std::sin(10 * kDeg);  // turned clockwise by 10 degrees
      moved.pose.east_m = c * p.x() + sn * p.y() + 50, moved.pose.north_m = -sn * p.x() + c * p.y() - 30;
      moved.pose.heading_deg = std::fmod(heading + 10, 360.0);
      s->estimate.push_back(moved);
    }
  }
  s->buoy = (s->dir / "buoy.csv").string();
  std::ofstream out(s->buoy);
  out << "time_s,lat,lon\n";
  const double reach = TetherReach(5, 3);
  TowedBuoy buoy(Eigen::Vector2d(0, -reach));
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.1);
  for (size_t i = 0; i + 1 < s->truth.size(); ++i) {
    const VehiclePose &a = s->truth[i].pose, &b = s->truth[i + 1].pose;
    for (int step = 0; step < 50; ++step) {
      const double f = step / 50.0;
      buoy.Step({a.east_m + f * (b.east_m - a.east_m), a.north_m + f * (b.north_m - a.north_m)}, reach);
    }
    const LatLon ll = frame.ToLatLon({buoy.position().x() + noise(rng), buoy.position().y() + noise(rng)});
    char line[96];
    std::snprintf(line, sizeof line, "%.1f,%.10f,%.10f\n", *s->truth[i + 1].time_s, ll.lat, ll.lon);
    out << line;
  }
}

BuoyGeorefOptions Options(const Scene& s) {
  BuoyGeorefOptions o;
  o.keyframes_source = "the vo trajectory";
  o.buoy_file = s.buoy;
  o.tether_length_m = 5;
  o.georef.tether_length_m = 5;
  o.depth_m = 3;
  o.report = (s.dir / "report.json").string();
  o.quiet = true;
  return o;
}

TEST(TrajectoryGeorefTest, TheBuoyUndoesTheTurnAndShiftOfATrajectoryWithoutFixes) {
  Scene s;
  Make(&s);
  const TrajectoryGeoref placed = GeoreferenceTrajectory(s.estimate, LocalFrame({43.1, 131.9}), Options(s));
  ASSERT_EQ(placed.rows.size(), s.truth.size());
  EXPECT_NEAR(placed.scale, 1.0, 0.02);
  EXPECT_NEAR(placed.rotation_deg, -10, 1.0);  // the fit turns it back
  EXPECT_GT(placed.shift_m, 50);
  EXPECT_GT(placed.good, static_cast<int>(s.truth.size()) / 2);
  double sum2 = 0, worst_heading = 0;
  for (size_t i = 0; i < s.truth.size(); ++i) {
    const VehiclePose &p = placed.rows[i].pose, &t = s.truth[i].pose;
    sum2 += std::pow(p.east_m - t.east_m, 2) + std::pow(p.north_m - t.north_m, 2);
    worst_heading = std::max(worst_heading, std::abs(std::remainder(p.heading_deg - t.heading_deg, 360.0)));
    EXPECT_EQ(placed.rows[i].image, s.truth[i].image);
    EXPECT_EQ(p.depth_m, t.depth_m);  // depth and altitude as estimated
    EXPECT_EQ(p.altitude_m, t.altitude_m);
  }
  const double rmse = std::sqrt(sum2 / s.truth.size());
  std::printf(
      "turned %.2f deg, moved %.1f m, scale %.4f: %.3f m RMS from the truth (predicted %.3f), heading within "
      "%.2f deg\n",
      placed.rotation_deg, placed.shift_m, placed.scale, rmse, placed.predicted_rmse_m, worst_heading);
  EXPECT_LT(rmse, 0.15);
  EXPECT_LT(rmse, 3 * placed.predicted_rmse_m + 0.02);
  EXPECT_LT(worst_heading, 1.0);
  std::ifstream report(s.dir / "report.json");
  EXPECT_TRUE(report.good()) << "no report";
}

TEST(TrajectoryGeorefTest, ARowWithoutATimeIsNamed) {
  Scene s;
  Make(&s);
  s.estimate[3].time_s.reset();
  try {
    GeoreferenceTrajectory(s.estimate, LocalFrame({43.1, 131.9}), Options(s));
    FAIL() << "placed a row without a time";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "time_s");
    EXPECT_NE(std::string(e.what()).find("f3.png"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace seamap
