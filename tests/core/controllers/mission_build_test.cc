#include "core/controllers/mission_build.h"

#include <filesystem>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

// A short line of constant-valued PNG frames over a flat seabed.
class MissionBuildTest : public ::testing::Test {
 protected:
  MissionBuildTest() {
    options_.camera = CameraFromFocalLength(8, 12.9, 160, 120);
    options_.frame = LocalFrame({43.1, 131.9});
    options_.config.map.base_zoom = 25;
    options_.config.map.min_zoom = 22;
    options_.out = (dir_ / "m.mbtiles").string();
    for (int i = 0; i < 4; ++i) {
      const std::string name = "f" + std::to_string(i) + ".png";
      cv::imwrite((dir_ / name).string(), cv::Mat(120, 160, CV_8UC1, cv::Scalar::all(60 + 40 * i)));
      FrameSpec f;
      f.index = i;
      f.image = name;
      f.image_path = (dir_ / name).string();
      f.time_s = i;
      f.pose.east_m = 0.5 * i;
      f.pose.altitude_m = 2.0;
      options_.survey.frames.push_back(f);
    }
  }

  std::string State(const MissionBuild& build) const { return build.store()->Metadata()["seamap_state"]; }

  testing::TempDir dir_;
  MissionBuildOptions options_;
};

TEST_F(MissionBuildTest, BuildsTheWholeSurveyWithCheckpoints) {
  int progress_calls = 0, finished_calls = 0;
  MissionObserver observer;
  observer.on_progress = [&](const BuildStats&) { ++progress_calls; };
  observer.on_layers_finished = [&] { ++finished_calls; };
  MissionBuild build(options_, observer);
  ASSERT_TRUE(build.Open());
  build.Start();
  build.Run();
  EXPECT_EQ(build.stats().frames_used, 4);
  EXPECT_EQ(progress_calls, 4);
  EXPECT_EQ(finished_calls, 1);
  EXPECT_EQ(build.layers(), std::vector<std::string>{"raw"});
  EXPECT_EQ(build.enhanced_stats(), nullptr);
  EXPECT_EQ(State(build), "complete");
  EXPECT_EQ(build.store()->Metadata()["seamap_layers"], "raw");
  EXPECT_GT(build.store()->TileCount(), 0);
}

TEST_F(MissionBuildTest, AppendingFramesAlreadyInTheMapLeavesNothingToBuild) {
  {
    MissionBuild first(options_);
    ASSERT_TRUE(first.Open());
    first.Start();
    first.Run();
  }
  options_.append = true;
  std::vector<std::string> notes;
  MissionObserver observer;
  observer.on_note = [&](const std::string& note) { notes.push_back(note); };
  MissionBuild again(options_, observer);
  EXPECT_FALSE(again.Open());
  EXPECT_EQ(again.skipped().size(), 4u);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("4 frames are in the map already"), std::string::npos) << notes[0];
}

TEST_F(MissionBuildTest, AnExistingMapIsRefusedWithoutAppendOrOverwrite) {
  {
    MissionBuild first(options_);
    ASSERT_TRUE(first.Open());
  }
  MissionBuild again(options_);
  try {
    again.Open();
    FAIL() << "an existing map was opened";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--out");
  }
}

TEST_F(MissionBuildTest, LiveBuildTellsTheObserverOfFramesAndCommittedTiles) {
  options_.live = true;
  int frames_placed = 0;
  size_t tiles_committed = 0;
  MissionObserver observer;
  observer.on_frame_placed = [&](const FrameRecord&, const TrackPoint&) { ++frames_placed; };
  observer.on_tiles_committed = [&](const std::string& layer, const std::vector<CommittedTile>& done) {
    EXPECT_EQ(layer, "");
    tiles_committed += done.size();
  };
  RecordedFeed feed(options_.survey, /*speed=*/0);
  MissionBuild build(options_, observer);
  ASSERT_TRUE(build.Open());
  // What a client needs is there before the first frame.
  EXPECT_EQ(State(build), "building");
  EXPECT_EQ(build.store()->Metadata()["seamap_layers"], "raw");
  EXPECT_EQ(build.store()->Metadata().count("seamap_trajectory"), 0u);
  build.Start();
  build.Run(feed);
  build.Conclude(true);
  EXPECT_EQ(frames_placed, 4);
  EXPECT_GT(tiles_committed, 0u);
  EXPECT_EQ(build.stats().frames_used, 4);
  EXPECT_EQ(State(build), "complete");
}

TEST_F(MissionBuildTest, LiveBuildNotCompleteIsMarkedStopped) {
  options_.live = true;
  FrameList none;
  RecordedFeed feed(none, 0);
  MissionBuild build(options_);
  ASSERT_TRUE(build.Open());
  build.Start();
  build.Conclude(false);
  EXPECT_EQ(State(build), "stopped");
}

TEST_F(MissionBuildTest, LiveFilteredBuildRecordsItsTrajectoryMode) {
  options_.live = true;
  options_.poses.mode = PoseMode::kFilter;
  options_.poses.filter.mode = EstimatorMode::kVo;
  MissionBuild build(options_);
  ASSERT_TRUE(build.Open());
  EXPECT_EQ(build.store()->Metadata()["seamap_trajectory"], R"({"mode":"vo"})");
}

TEST_F(MissionBuildTest, CheckRefusesWhatALiveBuildCannotDo) {
  options_.live = true;
  options_.resume = true;
  try {
    options_.Check();
    FAIL() << "a live build accepted --resume";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--resume");
  }
  options_.resume = false;
  options_.poses.mode = PoseMode::kRefine;
  EXPECT_THROW(MissionBuild build(options_), InputError);
  options_.poses.mode = PoseMode::kNavigation;
  options_.out.clear();
  EXPECT_THROW(options_.Check(), InputError);
}

}  // namespace
}  // namespace seamap
