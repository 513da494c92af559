// `seamap replay --nav-mode vo|ekf` end to end (issue 30, part 7): the small
// drifting survey replayed as fast as possible with the navigation filter
// online. The mission ends complete, keeps the filter's trajectory beside the
// navigation's, writes it (--trajectory-out), and that trajectory meets the
// bounds `seamap trajectory --mode vo|ekf` meets on the same survey
// (trajectory_test.cc); the map's texture sits where the trajectory says.
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/mission/mission_metadata.h"
#include "core/mission/mission_trajectory.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;

const testing::SimulatedSurvey& Survey() {
  return testing::DriftingSurvey();
}

// trajectory-eval's figures for `estimate` against the survey's truth.
nlohmann::json EvaluateTrajectory(const std::string& estimate, const testing::TempDir& dir) {
  const std::string json = (dir / "trajectory_eval.json").string();
  std::string log;
  EXPECT_EQ(Seamap("trajectory-eval " + estimate + " " + Survey().dir + "/nav_truth.csv --origin " + Survey().origin +
                       " --json " + json,
                   &log),
            0)
      << log;
  return nlohmann::json::parse(std::ifstream(json));
}

// map-eval's figures (texture offset against the truth) for the map.
nlohmann::json EvaluateMap(const std::string& map, const testing::TempDir& dir) {
  const std::string json = (dir / "map_eval.json").string();
  std::string log;
  EXPECT_EQ(Seamap("map-eval " + map + " " + Survey().dir + " --json " + json, &log), 0) << log;
  return nlohmann::json::parse(std::ifstream(json));
}

struct Replayed {
  nlohmann::json trajectory, map;
};

// Replays the survey with `mode`; checks the mission is complete and holds the filter's trajectory.
Replayed ReplayWith(const std::string& mode, const testing::TempDir& dir) {
  const std::string map = (dir / (mode + ".mbtiles")).string(), csv = (dir / (mode + ".csv")).string();
  std::string log;
  EXPECT_EQ(Seamap("replay " + Survey().dir + " --out " + map + " --nav-mode " + mode +
                       " --nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5 --speed max --exit-when-done --quiet"
                       " --host 127.0.0.1 --port 0 --trajectory-out " +
                       csv,
                   &log),
            0)
      << log;
  EXPECT_NE(log.find("replay complete: frames used 160, rejected 0"), std::string::npos) << log;
  EXPECT_NE(log.find("trajectory (estimated): 160 frames -> " + csv), std::string::npos) << log;
  {
    MBTilesStore store(map, MBTilesStore::Mode::kReadOnly);
    EXPECT_EQ(ReadMissionMetadata(store).StateOrEmpty(), "complete");
    const MissionTrajectory held = MissionTrajectory::Read(store);
    EXPECT_EQ(held.placed(), TrajectorySource::kEstimated);
    EXPECT_EQ(held.Poses(TrajectorySource::kEstimated).size(), 160u);
    EXPECT_EQ(held.Poses(TrajectorySource::kNav).size(), 160u);
  }
  return {EvaluateTrajectory(csv, dir), EvaluateMap(map, dir)};
}

void Print(const std::string& mode, const Replayed& r) {
  std::printf(
      "replay --nav-mode %s: ATE %.1f mm, drift %.2f %% of distance, max error %.1f mm; map offset median "
      "%.1f mm, p90 %.1f mm\n",
      mode.c_str(), 1000 * r.trajectory["ate_m"].get<double>(), r.trajectory["drift_percent"].get<double>(),
      1000 * r.trajectory["max_error_m"].get<double>(), r.map["median_mm"].get<double>(),
      r.map["p90_mm"].get<double>());
}

// The map's texture is off the truth by what the trajectory is off: its median block offset within
// the trajectory's RMS error, and its p90 within its largest error (plus a base pixel each: the
// blocks are measured to about a pixel).
void ExpectMapConsistent(const Replayed& r) {
  const double pixel_mm = r.map["pixel_mm"].get<double>();
  EXPECT_GT(r.map["coverage"].get<double>(), 0.9);
  EXPECT_LT(r.map["median_mm"].get<double>(), 1000 * r.trajectory["ate_m"].get<double>() + pixel_mm);
  EXPECT_LT(r.map["p90_mm"].get<double>(), 1000 * r.trajectory["max_error_m"].get<double>() + pixel_mm);
}

// vo: the photos, not the drifting navigation. On this survey `trajectory --mode vo` drifts 0.98 %
// of the distance (ATE 98 mm; the navigation 1.76 %, 154 mm) and the replay gives the same
// trajectory to the digit; the bound is trajectory_test's.
TEST(ReplayNavMode, VisualOdometryLiveMeetsTheBatchBoundsAndTheMapFollowsIt) {
  testing::TempDir dir;
  const Replayed vo = ReplayWith("vo", dir);
  Print("vo", vo);
  EXPECT_LT(vo.trajectory["drift_percent"].get<double>(), 1.0);
  EXPECT_LT(vo.trajectory["ate_m"].get<double>(), 0.12);
  ExpectMapConsistent(vo);
  // Better than the drifting navigation's map (median 45 mm on this survey).
  EXPECT_LT(vo.map["median_mm"].get<double>(), 25);
}

// ekf: the navigation's positions fused, gated. With its noise given as 5 mm the filter follows the
// drifting fixes: `trajectory --mode ekf` gives ATE 154.3 mm here against the navigation's 154.5 mm,
// and the replay the same; the filter must not be worse than the fixes it fuses.
TEST(ReplayNavMode, FilterWithFixesLiveMeetsTheBatchBoundsAndTheMapFollowsIt) {
  testing::TempDir dir;
  const Replayed ekf = ReplayWith("ekf", dir);
  Print("ekf", ekf);
  const nlohmann::json nav = EvaluateTrajectory(Survey().nav, dir);
  EXPECT_LT(ekf.trajectory["ate_m"].get<double>(), nav["ate_m"].get<double>() + 0.005);
  EXPECT_LT(ekf.trajectory["end_error_m"].get<double>(), nav["end_error_m"].get<double>() + 0.005);
  ExpectMapConsistent(ekf);
}

}  // namespace
}  // namespace seamap
