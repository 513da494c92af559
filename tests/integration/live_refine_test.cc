// `seamap replay --refine-nav` end to end on a small drifting survey at its
// pace: the navigation is refined while the frames come (the seams fall as
// the vehicle crosses its first line), and the mission it leaves is refined,
// complete, and the map that `build --refine-nav` makes of the same survey.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/tiles/mbtiles_store.h"
#include "core/tiles/tile_codec.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;

// 72 frames (14 s) over three 3 m lines 0.9 m apart; the navigation drifting
// 1 m/min, with 5 mm and 0.5 degree noise: the second line crosses the first
// after about 6 s.
const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("live_refine",
                               "--frames 72 --line-length 3 --line-spacing 0.9 --nav-drift 1 --nav-noise 0.005 "
                               "--heading-noise 0.5 --image-format jpg --seed 5 --quiet");
}

// The navigation's stated noise.
const char kNoise[] = " --nav-noise 0.005 --nav-drift 1 --heading-noise 0.5";

nlohmann::json Evaluate(const std::string& estimate) {
  testing::TempDir dir;
  const std::string json = (dir / "eval.json").string();
  std::string log;
  EXPECT_EQ(Seamap("trajectory-eval " + estimate + " " + Survey().dir + "/nav_truth.csv --origin " + Survey().origin +
                       " --json " + json,
                   &log),
            0)
      << log;
  return nlohmann::json::parse(std::ifstream(json));
}

nlohmann::json MapEval(const std::string& map) {
  testing::TempDir dir;
  const std::string json = (dir / "eval.json").string();
  std::string log;
  EXPECT_EQ(Seamap("map-eval " + map + " " + Survey().dir + " --json " + json, &log), 0) << log;
  return nlohmann::json::parse(std::ifstream(json));
}

TEST(LiveRefine, ReplayLeavesTheMapBuildRefineNavMakes) {
  testing::TempDir dir;
  const std::string built = (dir / "built.mbtiles").string(), replayed = (dir / "replayed.mbtiles").string();
  const std::string built_csv = (dir / "built.csv").string(), replayed_csv = (dir / "replayed.csv").string();
  std::string log;
  ASSERT_EQ(
      Seamap(Survey().BuildArgs() + kNoise + " --refine-nav --out " + built + " --trajectory-out " + built_csv, &log),
      0)
      << log;
  ASSERT_EQ(Seamap("replay " + Survey().dir + kNoise + " --refine-nav --out " + replayed + " --trajectory-out " +
                       replayed_csv + " --speed 1 --host 127.0.0.1 --port 0 --quiet --exit-when-done",
                   &log),
            0)
      << log;
  EXPECT_NE(log.find("replay complete"), std::string::npos) << log;

  // During the replay: a solve closed the seams (its pairs' disagreement with
  // the navigation against the solution) and frames were painted again.
  const size_t solve = log.find("refine live: solve ");
  ASSERT_NE(solve, std::string::npos) << "no live solve: " << log;
  double before_mm = 0, after_mm = 0;
  const size_t rms = log.find("pair residual RMS ", solve);
  ASSERT_NE(rms, std::string::npos) << log;
  ASSERT_EQ(std::sscanf(log.c_str() + rms, "pair residual RMS %lf mm -> %lf mm", &before_mm, &after_mm), 2) << log;
  std::printf("first live solve: pair residual %.1f mm -> %.1f mm\n", before_mm, after_mm);
  EXPECT_GT(before_mm, 10);
  EXPECT_LT(after_mm, 5);
  EXPECT_EQ(log.find("refine live: 0 solves"), std::string::npos) << log;
  EXPECT_EQ(log.find(" 0 frames painted again"), std::string::npos) << log;

  // The trajectory: refined as build refines it (seams from 0.1 m down to a few mm).
  const auto refined = Evaluate(replayed_csv), by_build = Evaluate(built_csv), raw = Evaluate(Survey().nav);
  std::printf("replay --refine-nav: cross-pass p90 %.1f mm (build --refine-nav %.1f mm, navigation %.1f mm)\n",
              refined["cross_p90_mm"].get<double>(), by_build["cross_p90_mm"].get<double>(),
              raw["cross_p90_mm"].get<double>());
  EXPECT_GT(raw["cross_p90_mm"].get<double>(), 50);
  EXPECT_LT(refined["cross_p90_mm"].get<double>(), 20);
  EXPECT_NEAR(refined["cross_p90_mm"].get<double>(), by_build["cross_p90_mm"].get<double>(), 1.0);

  // The map: every base tile the build painted is the replay's to within a grey level or two.
  MBTilesStore a(built, MBTilesStore::Mode::kReadOnly), b(replayed, MBTilesStore::Mode::kReadOnly);
  const int base_zoom = std::stoi(a.Metadata().at("maxzoom"));
  int tiles = 0, differing = 0;
  double worst_mean = 0;
  for (const TileId& id : a.TileIds()) {
    if (id.z != base_zoom) continue;
    ++tiles;
    const auto other = b.GetTile(id);
    ASSERT_TRUE(other) << "tile " << id.z << "/" << id.x << "/" << id.y << " missing from the replay";
    const cv::Mat ta = DecodeTile(*a.GetTile(id)), tb = DecodeTile(*other);
    ASSERT_EQ(ta.size(), tb.size());
    cv::Mat diff;
    cv::absdiff(ta, tb, diff);
    const double mean = cv::mean(diff.reshape(1))[0];
    worst_mean = std::max(worst_mean, mean);
    differing += mean > 0;
  }
  std::printf("replay --refine-nav: %d of %d base tiles differ from build's, worst mean difference %.3f\n", differing,
              tiles, worst_mean);
  EXPECT_GT(tiles, 10);
  EXPECT_LT(worst_mean, 2.0);
  const auto eval_built = MapEval(built), eval_replayed = MapEval(replayed);
  std::printf("map-eval p90: replay %.3f px, build %.3f px\n", eval_replayed["p90_px"].get<double>(),
              eval_built["p90_px"].get<double>());
  EXPECT_NEAR(eval_replayed["p90_px"].get<double>(), eval_built["p90_px"].get<double>(), 0.1);

  // The mission: refined and complete, with the report build keeps.
  ASSERT_EQ(Seamap("info " + replayed, &log), 0) << log;
  EXPECT_NE(log.find("complete"), std::string::npos) << log;
  EXPECT_NE(log.find("trajectory corrected"), std::string::npos) << log;
  EXPECT_NE(b.Metadata().at("seamap_trajectory").find("\"registered_cross_line\""), std::string::npos);
}

}  // namespace
}  // namespace seamap
