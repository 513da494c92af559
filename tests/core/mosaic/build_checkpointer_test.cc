// Crash-safe builds: a builder dropped at any point (as a killed process
// leaves its store: committed batches, the last checkpoint) and resumed
// gives the same tiles, byte for byte, as one that never stopped; a failed
// --append leaves the map as it was.
#include "core/mosaic/build_checkpointer.h"

#include <filesystem>
#include <map>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "core/mosaic/mosaic_builder.h"
#include "core/tiles/mbtiles_store.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(BuildCheckpointer, BlobsKeepSumsAndWeightsExactly) {
  TileAccumulator tile(256, 3, 0, 0);
  cv::Mat sums(256, 256, CV_32FC3), weights(256, 256, CV_32F);
  cv::randu(sums, 0, 1e4);
  cv::randu(weights, 0, 40);
  weights(cv::Rect(0, 0, 100, 256)).setTo(0);  // uncovered: compresses to almost nothing
  tile.Restore(sums, weights);
  const auto [s, w] = UnpackSums(PackSums(tile), 256, 3);
  EXPECT_EQ(cv::norm(s, sums, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(w, weights, cv::NORM_INF), 0);
  cv::Mat kept(256, 256, CV_16U);
  cv::randu(kept, 0, 65535);
  EXPECT_EQ(cv::norm(UnpackWeights(PackWeights(kept), 256), kept, cv::NORM_INF), 0);
  std::vector<uint8_t> damaged = PackWeights(kept);
  damaged.resize(damaged.size() / 2);
  EXPECT_THROW(UnpackWeights(damaged, 256), std::runtime_error);
  EXPECT_THROW(UnpackSums(PackWeights(kept), 256, 3), std::runtime_error);
}

TEST(BuildCheckpointer, ProgressRoundTrips) {
  BuildProgress p;
  p.frame_index = 41;
  p.handover_index = 40;
  p.kept = {{{25, 3, 4}, 9}};
  p.tiles = {{{25, 1, 2}, 17}};
  p.settings = {{"tile_size", 256}};
  p.command = "seamap build --out 'my map.mbtiles'";
  const BuildProgress q = BuildProgress::FromJson(p.ToJson().dump());
  EXPECT_EQ(q.ToJson(), p.ToJson());
  EXPECT_THROW(BuildProgress::FromJson("{}"), std::runtime_error);
}

class ResumeTest : public ::testing::Test {
 protected:
  ResumeTest() : camera_(CameraFromFocalLength(8, 12.9, 160, 120)), frame_({43.1, 131.9}) {
    config_.map.base_zoom = 25;
    config_.map.min_zoom = 22;
    // A look-ahead shorter than the way back: tiles of the first line are
    // finished, then read back with the weights they had.
    config_.buffer.lookahead_frames = 12;
    config_.buffer.batch_frames = 3;
    config_.buffer.batch_seconds = 0;
    config_.buffer.checkpoint_seconds = 1e-9;  // at every batch
    frames_ = TwoLines();
  }

  // Two lines there and back of textured frames, one image missing.
  std::vector<FrameSpec> TwoLines() {
    std::vector<FrameSpec> frames;
    cv::RNG rng(3);
    const double step = camera_.height * 2.0 / camera_.fy / 8, spacing = camera_.width * 2.0 / camera_.fx * 0.6;
    for (int i = 0; i < 40; ++i) {
      const bool back = i >= 20;
      const std::string path = (dir_ / ("t" + std::to_string(i) + ".png")).string();
      cv::Mat texture(camera_.height, camera_.width, CV_8U);
      rng.fill(texture, cv::RNG::UNIFORM, 40, 220);
      if (i != 13) cv::imwrite(path, texture);
      FrameSpec f;
      f.index = i;
      f.image = "t" + std::to_string(i) + ".png";
      f.image_path = path;
      f.pose.east_m = back ? spacing : 0;
      f.pose.north_m = step * (back ? 39 - i : i);
      f.pose.heading_deg = (back ? 180 : 0) + rng.uniform(-2.0, 2.0);
      f.pose.roll_deg = rng.uniform(-1.0, 1.0);
      f.pose.altitude_m = 2.0;
      frames.push_back(f);
    }
    return frames;
  }

  // Builds frames [0, stop) (all when stop < 0) into `path`, resuming when
  // asked; stopping early drops the builder unfinished, as a crash would
  // (`unfinished`: so does having pushed them all).
  BuildStats Build(const std::string& path, bool resume, int stop, const BuildConfig& config, bool unfinished = false) {
    MBTilesStore store(path);
    MosaicPlan plan = PlanMosaic(config.map, camera_, frame_, frames_, 1);
    BuildStart start;
    start.checkpoints = true;
    start.resume = resume;
    start.frames_total = static_cast<int>(frames_.size());
    MosaicBuilder builder(config, camera_, frame_, plan, &store, {}, start);
    builder.Foresee(frames_);
    for (const FrameSpec& f : frames_) {
      if (stop >= 0 && f.index >= stop) return builder.stats();
      builder.Push(f);
    }
    if (unfinished) return builder.stats();
    builder.Finish();
    return builder.stats();
  }

  testing::TempDir dir_;
  CameraModel camera_;
  LocalFrame frame_;
  BuildConfig config_;
  std::vector<FrameSpec> frames_;
};

TEST_F(ResumeTest, AResumedBuildEqualsOneThatNeverStopped) {
  const std::string whole = (dir_ / "whole.mbtiles").string();
  const BuildStats uninterrupted = Build(whole, false, -1, config_);
  EXPECT_GT(uninterrupted.readbacks, 0);
  MBTilesStore reference(whole, MBTilesStore::Mode::kReadOnly);
  const std::vector<TileId> ids = reference.TileIds();

  // Stopped on the first line, where the missing frame is, and on the way back; twice in a row.
  for (const std::vector<int>& stops : {std::vector<int>{14}, std::vector<int>{2, 27}, std::vector<int>{20, 33}}) {
    const std::string path = (dir_ / ("stopped" + std::to_string(stops[0]) + ".mbtiles")).string();
    bool resume = false;
    for (int stop : stops) {
      Build(path, resume, stop, config_);
      resume = true;
      MBTilesStore reader(path, MBTilesStore::Mode::kReadOnly);
      EXPECT_EQ(reader.Metadata().at("seamap_state"), "building");
      EXPECT_TRUE(reader.ReadCheckpoint());
    }
    const BuildStats resumed = Build(path, true, -1, config_);
    EXPECT_EQ(resumed.frames_used, uninterrupted.frames_used);
    EXPECT_EQ(resumed.rejections.size(), uninterrupted.rejections.size());
    EXPECT_EQ(resumed.readbacks, uninterrupted.readbacks);
    MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
    EXPECT_EQ(store.Metadata().at("seamap_state"), "complete");
    EXPECT_EQ(store.Metadata().at("bounds"), reference.Metadata().at("bounds"));
    EXPECT_FALSE(store.ReadCheckpoint());
    EXPECT_EQ(store.TileIds().size(), ids.size());
    for (const TileId& id : ids) {
      auto a = reference.GetTile(id), b = store.GetTile(id);
      ASSERT_TRUE(b) << "stopped at " << stops[0] << ": tile " << id.z << "/" << id.x << "/" << id.y << " missing";
      EXPECT_TRUE(*a == *b) << "stopped at " << stops[0] << ": tile " << id.z << "/" << id.x << "/" << id.y;
    }
    const auto frames = store.Frames();
    const auto track = store.Track();
    ASSERT_EQ(frames.size(), frames_.size());
    ASSERT_EQ(track.size(), frames_.size());
    for (size_t i = 0; i < frames.size(); ++i) {
      EXPECT_EQ(frames[i].id, static_cast<int>(i));
      EXPECT_EQ(frames[i].image, frames_[i].image);
      EXPECT_EQ(track[i].seq, static_cast<int>(i));
    }
  }
}

TEST_F(ResumeTest, NoCheckpointsWhenCheckpointSecondsIsZero) {
  const std::string path = (dir_ / "m.mbtiles").string();
  BuildConfig off = config_;
  off.buffer.checkpoint_seconds = 0;
  Build(path, false, 10, off);
  MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
  EXPECT_EQ(store.Metadata().at("seamap_state"), "building");
  EXPECT_FALSE(store.ReadCheckpoint());
  EXPECT_THROW(Build(path, true, -1, config_), InputError);  // nothing to resume from
}

TEST_F(ResumeTest, OtherSettingsAreRefusedByName) {
  const std::string path = (dir_ / "m.mbtiles").string();
  Build(path, false, 10, config_);
  BuildConfig other = config_;
  other.blend.feather_power = 2;
  try {
    Build(path, true, -1, other);
    ADD_FAILURE() << "resumed with another feather_power";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "feather_power");
  }
}

TEST_F(ResumeTest, AFailedAppendLeavesTheMapAsItWas) {
  std::vector<FrameSpec> all = frames_;
  BuildConfig rarely = config_;
  rarely.buffer.checkpoint_seconds = 1e6;  // no checkpoint after the start
  // Failing before any checkpoint after the start, and after several (config_: one every batch).
  for (const BuildConfig* config : {&rarely, &config_}) {
    const std::string path = (dir_ / (config == &rarely ? "rarely.mbtiles" : "often.mbtiles")).string();
    frames_.assign(all.begin(), all.begin() + 20);
    Build(path, false, -1, config_);
    std::map<TileId, std::vector<uint8_t>> before;
    {
      MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
      for (const TileId& id : store.TileIds()) before[id] = *store.GetTile(id);
    }
    frames_.assign(all.begin() + 20, all.end());
    for (size_t i = 0; i < frames_.size(); ++i) frames_[i].index = static_cast<int>(i);
    // Every frame pushed, then dropped unfinished as when an exception went
    // through: one thread keeps at most 8 frames in flight, so 12 or more
    // were painted, and with config_ a checkpoint written every 3.
    BuildConfig one_thread = *config;
    one_thread.threads = 1;
    const BuildStats failed = Build(path, false, -1, one_thread, /*unfinished=*/true);
    EXPECT_GE(failed.checkpoints, config == &rarely ? 1 : 4);
    MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
    EXPECT_EQ(store.Metadata().at("seamap_state"), "complete");
    EXPECT_FALSE(store.ReadCheckpoint());
    EXPECT_EQ(store.Frames().size(), 20u);
    EXPECT_EQ(store.Track().size(), 20u);
    ASSERT_EQ(store.TileIds().size(), before.size());
    for (const auto& [id, bytes] : before)
      EXPECT_TRUE(*store.GetTile(id) == bytes) << id.z << "/" << id.x << "/" << id.y;
  }
}

TEST_F(ResumeTest, ASuccessfulAppendKeepsNoVersionsFromBeforeIt) {
  const std::string path = (dir_ / "m.mbtiles").string();
  std::vector<FrameSpec> all = frames_;
  frames_.assign(all.begin(), all.begin() + 20);
  Build(path, false, -1, config_);
  frames_.assign(all.begin() + 20, all.end());
  for (size_t i = 0; i < frames_.size(); ++i) frames_[i].index = static_cast<int>(i);
  Build(path, false, -1, config_);
  MBTilesStore store(path);
  EXPECT_EQ(store.Metadata().at("seamap_state"), "complete");
  EXPECT_EQ(store.Frames().size(), 40u);
  EXPECT_FALSE(store.RollBackToStart());  // the append is over: nothing to return to
  EXPECT_EQ(store.Frames().size(), 40u);
}

}  // namespace
}  // namespace seamap
