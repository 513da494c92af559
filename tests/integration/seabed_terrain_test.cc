// The height model from the photos of a real simulated survey over relief
// (`seamap simulate --relief`): rendered, JPEG-compressed frames, SIFT
// features, the whole EstimateSeabedTerrain chain, against truth/terrain.tif.
#include <cmath>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/nav/frame_list.h"
#include "core/nav/nav_reader.h"
#include "core/terrain/height_grid_io.h"
#include "core/trajectory/seabed_terrain.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

// 120 frames over lanes 0.9 m apart at 2 m altitude, relief 0.3 m rms; half
// the default image size with half the focal length (the same field of view).
const testing::SimulatedSurvey& ReliefSurvey() {
  return testing::SharedSurvey("relief_dem",
                               "--frames 120 --line-length 5 --line-spacing 0.9 --relief 0.3 --altitude-min 2 "
                               "--altitude-max 2 --width 348 --height 260 --focal-mm 4 --image-format jpg "
                               "--seed 5 --quiet");
}

struct Loaded {
  LatLon origin;
  CameraModel camera;
  FrameList frames;
};

Loaded Load(const testing::SimulatedSurvey& survey, const std::string& nav_name) {
  Loaded l;
  const nlohmann::json description = nlohmann::json::parse(std::ifstream(survey.dir + "/survey.json"));
  l.origin = {description.at("origin").at(0).get<double>(), description.at("origin").at(1).get<double>()};
  l.camera = LoadCamera(survey.camera);
  NavReadOptions options;
  options.origin = l.origin;
  l.frames = MatchFrames(ReadNavigation(survey.dir + "/" + nav_name, options), survey.photo, std::nullopt);
  return l;
}

TEST(SeabedTerrainSurvey, HeightModelFromThePhotosMatchesTheTruth) {
  const Loaded survey = Load(ReliefSurvey(), "nav_truth.csv");
  ASSERT_EQ(survey.frames.frames.size(), 120u);
  TerrainOptions options;
  options.threads = 2;
  TerrainReport report;
  int progress_calls = 0;
  const HeightGrid grid = EstimateSeabedTerrain(survey.frames.frames, survey.camera, options, &report,
                                                [&](const std::string&, int, int) { ++progress_calls; });
  ASSERT_FALSE(grid.empty());
  EXPECT_GT(progress_calls, 100);
  EXPECT_EQ(report.frames_unreadable, 0);
  EXPECT_TRUE(grid.has_depth_datum);
  const HeightGrid truth = ReadHeightGridGeotiff(ReliefSurvey().dir + "/truth/terrain.tif", survey.origin);
  std::vector<double> error, sigma;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      double t = 0;
      if (!std::isfinite(grid.height_m(r, c)) || !truth.Sample(grid.CellCentre(r, c), &t)) continue;
      error.push_back(grid.height_m(r, c) - t);
      sigma.push_back(grid.sigma_m(r, c));
    }
  ASSERT_GT(error.size(), 100u);
  double mean = 0;
  for (double e : error) mean += e / error.size();
  double sum = 0, within1 = 0, within2 = 0;
  for (size_t k = 0; k < error.size(); ++k) {
    sum += (error[k] - mean) * (error[k] - mean);
    within1 += std::fabs(error[k] - mean) <= sigma[k];
    within2 += std::fabs(error[k] - mean) <= 2 * sigma[k];
  }
  const double rms = std::sqrt(sum / error.size());
  const double coverage = static_cast<double>(error.size()) / report.fit.cells_swath;
  // Heights are metres up from the sea surface: the absolute offset is small too.
  EXPECT_LT(std::fabs(mean), 0.05);
  // A small survey at half resolution: sparser points and more swath edge
  // than the (scripts/bench_dem.sh holds that one to 20 mm over
  // 90 %); measured 21.6 mm over 82 %.
  EXPECT_LT(rms, 0.030) << "cell " << report.fit.cell_m << " points " << report.tracks.points;
  EXPECT_GT(coverage, 0.75);
  // The sigmas say the error they make: about 68 % within one, 95 % within two.
  EXPECT_GT(within1 / error.size(), 0.6) << within2 / error.size();
  EXPECT_LT(within1 / error.size(), 0.9);
  EXPECT_GT(within2 / error.size(), 0.9);
}

}  // namespace
}  // namespace seamap
