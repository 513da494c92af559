#include "core/trajectory/seabed_terrain.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/core/trajectory/synthetic_seabed.h"

namespace seamap {
namespace {

using testing_seabed::Lawnmower;
using testing_seabed::Relief;
using testing_seabed::Scene;

struct Accuracy {
  double rms_m = 0, coverage = 0, within1 = 0, within2 = 0;
};

// The grid against the relief over the swath, after removing the mean offset.
Accuracy Measure(const HeightGrid& grid, const Relief& relief, const TerrainReport& report) {
  std::vector<double> error, sigma;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      if (!std::isfinite(grid.height_m(r, c))) continue;
      const LocalXY p = grid.CellCentre(r, c);
      error.push_back(grid.height_m(r, c) - relief.Up(p.east, p.north));
      sigma.push_back(grid.sigma_m(r, c));
    }
  Accuracy a;
  if (error.empty()) return a;
  double mean = 0;
  for (double e : error) mean += e / error.size();
  double sum = 0;
  for (size_t k = 0; k < error.size(); ++k) {
    const double e = std::fabs(error[k] - mean);
    sum += e * e;
    a.within1 += e <= sigma[k];
    a.within2 += e <= 2 * sigma[k];
  }
  a.rms_m = std::sqrt(sum / error.size());
  a.within1 /= error.size();
  a.within2 /= error.size();
  a.coverage = static_cast<double>(error.size()) / report.fit.cells_swath;
  return a;
}

Scene IssueScene(const Relief& relief) {
  Scene scene;
  scene.poses = Lawnmower(relief, 4, 6.0, 0.9, 0.15);  // lanes 0.9 m apart, 2 m altitude
  scene.ScatterOnRelief(relief, -2, 4.7, -2, 8, 150);
  return scene;
}

HeightGrid Estimate(const Scene& scene, TerrainReport* report) {
  return EstimateSeabedTerrainFromFeatures(
      scene.poses, scene.camera, [&](int i) { return scene.FeaturesOf(i); }, TerrainOptions(), report);
}

TEST(SeabedTerrain, HeightModelWithin20MillimetresOverTheSwath) {
  const Relief relief(0.3, 21);
  const Scene scene = IssueScene(relief);
  TerrainReport report;
  SeabedTracks tracks;
  const HeightGrid grid = EstimateSeabedTerrainFromFeatures(
      scene.poses, scene.camera, [&](int i) { return scene.FeaturesOf(i); }, TerrainOptions(), &report, nullptr,
      &tracks);
  ASSERT_FALSE(grid.empty());
  EXPECT_TRUE(grid.has_depth_datum);
  EXPECT_EQ(tracks.points.size(), static_cast<size_t>(report.tracks.points));
  const Accuracy a = Measure(grid, relief, report);
  EXPECT_LT(a.rms_m, 0.020) << "cell " << report.fit.cell_m;
  EXPECT_GT(a.coverage, 0.90);
  EXPECT_GT(a.within1, 0.5) << "within 2 sigma: " << a.within2;
  EXPECT_GT(a.within2, 0.85);
  // Conservative here: this scene's points are sparser than a survey's, and
  // the hold-out floor (9 mm against 7 mm rms) also holds the error between
  // cell centres; on simulated surveys 0.81 within 1 sigma (docs/TERRAIN.md).
  EXPECT_LT(a.within1, 0.99) << "rms " << a.rms_m << " floor " << report.fit.sigma_floor_m;
  // Metres up from the sea surface: the seabed is about 12 m down.
  double h = 0;
  ASSERT_TRUE(grid.Sample({0.9, 2}, &h));
  EXPECT_NEAR(h, relief.Up(0.9, 2), 0.05);
}

TEST(SeabedTerrain, StaysWithinBoundsWithFishParticlesAndFalseMatches) {
  const Relief relief(0.3, 22);
  Scene scene = IssueScene(relief);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> ue(-0.5, 2.3), un(0, 4), lift(0.2, 1.7);
  for (int k = 0; k < 300; ++k) {  // fish, some swimming, and particles
    const double e = ue(rng), n = un(rng);
    scene.points.push_back({{e, n, relief.Up(e, n) + lift(rng)}, scene.RandomDescriptor(&rng), k % 2 ? 0.03 : 0.0});
  }
  for (int k = 0; k < 300; ++k) scene.points[k + 300].descriptor = scene.points[k].descriptor;  // repeated texture
  scene.distractor_share = 0.2;
  TerrainReport report;
  const HeightGrid grid = Estimate(scene, &report);
  const Accuracy a = Measure(grid, relief, report);
  EXPECT_LT(a.rms_m, 0.025);
  EXPECT_GT(a.coverage, 0.90);
  EXPECT_GT(report.fit.points_rejected, 0);
}

TEST(SeabedTerrain, UnreadableImagesAreCountedAndNamed) {
  const Relief relief(0.1, 1);
  std::vector<FrameSpec> frames;
  for (const VehiclePose& p : Lawnmower(relief, 1, 1.0, 0.9, 0.25)) {
    FrameSpec f;
    f.index = static_cast<int>(frames.size());
    f.image = "missing_" + std::to_string(f.index) + ".jpg";
    f.image_path = "/nonexistent/" + f.image;
    f.pose = p;
    frames.push_back(f);
  }
  TerrainOptions options;
  options.threads = 2;
  TerrainReport report;
  const HeightGrid grid = EstimateSeabedTerrain(frames, testing_seabed::SmallCamera(), options, &report);
  EXPECT_TRUE(grid.empty());
  EXPECT_EQ(report.frames, static_cast<int>(frames.size()));
  EXPECT_EQ(report.frames_unreadable, static_cast<int>(frames.size()));
  ASSERT_FALSE(report.problems.empty());
  EXPECT_NE(report.problems[0].find("missing_0.jpg"), std::string::npos) << report.problems[0];
  options.tracks.min_overlap = 2;
  EXPECT_THROW(EstimateSeabedTerrain(frames, testing_seabed::SmallCamera(), options, &report), InputError);
}

}  // namespace
}  // namespace seamap
