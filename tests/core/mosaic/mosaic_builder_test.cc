#include "core/mosaic/mosaic_builder.h"

#include <filesystem>
#include <map>
#include <mutex>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "core/tiles/tile_codec.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

// Constant-valued frames over a flat seabed, written as PNG files.
class MosaicBuilderTest : public ::testing::Test {
 protected:
  MosaicBuilderTest() : camera_(CameraFromFocalLength(8, 12.9, 160, 120)), frame_({43.1, 131.9}) {
    config_.map.base_zoom = 25;
    config_.map.min_zoom = 22;
  }

  FrameSpec Frame(int index, double east, double north, uint8_t value, int channels = 1) {
    const std::string path = (dir_ / ("f" + std::to_string(index) + ".png")).string();
    cv::imwrite(path, cv::Mat(camera_.height, camera_.width, CV_8UC(channels), cv::Scalar::all(value)));
    FrameSpec f;
    f.index = index;
    f.image = "f" + std::to_string(index) + ".png";
    f.image_path = path;
    f.pose.east_m = east;
    f.pose.north_m = north;
    f.pose.altitude_m = 2.0;
    return f;
  }

  // Base-zoom tile and pixel under a local point.
  std::pair<TileId, cv::Point> TileAt(double east, double north) const {
    GlobalPixel p = LatLonToPixel(frame_.ToLatLon({east, north}), 25, 256);
    TileId id{25, static_cast<int>(p.x / 256), static_cast<int>(p.y / 256)};
    return {id, cv::Point(static_cast<int>(p.x - id.x * 256.0), static_cast<int>(p.y - id.y * 256.0))};
  }

  // Builds `frames` into a new MBTiles file named `name` with `config`.
  // With `foresee`, the builder is told the whole survey first (as an offline build is).
  std::pair<std::unique_ptr<TileStore>, BuildStats> BuildMap(const BuildConfig& config,
                                                             const std::vector<FrameSpec>& frames,
                                                             const std::string& name, bool foresee = false) {
    auto store = OpenTileStore((dir_ / name).string(), "png", true);
    MosaicPlan plan = PlanMosaic(config.map, camera_, frame_, frames, 1);
    MosaicBuilder builder(config, camera_, frame_, plan, store.get());
    if (foresee) builder.Foresee(frames);
    for (const auto& f : frames) builder.Push(f);
    builder.Finish();
    return {std::move(store), builder.stats()};
  }

  testing::TempDir dir_;
  CameraModel camera_;
  LocalFrame frame_;
  BuildConfig config_;
};

TEST_F(MosaicBuilderTest, RevisitedTileIsReadBackAndBlendedNotOverwritten) {
  auto store = OpenTileStore((dir_ / "m.mbtiles").string(), "png", true);
  std::vector<FrameSpec> frames{Frame(0, 0, 0, 100), Frame(1, 10, 0, 30), Frame(2, 0, 0, 200)};
  MosaicPlan plan = PlanMosaic(config_.map, camera_, frame_, frames, 1);
  MosaicBuilder builder(config_, camera_, frame_, plan, store.get());
  for (const auto& f : frames) builder.Push(f);
  builder.Finish();
  EXPECT_EQ(builder.stats().frames_used, 3);
  EXPECT_GT(builder.stats().readbacks, 0);  // frame 2 came back to frame 0's tiles

  auto [id, px] = TileAt(0, 0);
  auto bytes = store->GetTile(id);
  ASSERT_TRUE(bytes);
  cv::Mat tile = DecodeTile(*bytes);
  const cv::Vec2b centre = tile.at<cv::Vec2b>(px);
  EXPECT_EQ(centre[1], 255);
  EXPECT_NEAR(centre[0], 150, 3) << "frame 0 (100) and frame 2 (200) blended";
}

TEST_F(MosaicBuilderTest, ColourMapOfGrayLookingFramesReadsTilesBack) {
  // A mono camera saving RGB files: the colour map's tiles decode as gray,
  // and must still be read back and blended.
  auto store = OpenTileStore((dir_ / "m.mbtiles").string(), "png", true);
  std::vector<FrameSpec> frames{Frame(0, 0, 0, 100, 3), Frame(1, 10, 0, 30, 3), Frame(2, 0, 0, 200, 3)};
  MosaicPlan plan = PlanMosaic(config_.map, camera_, frame_, frames, 3);
  MosaicBuilder builder(config_, camera_, frame_, plan, store.get());
  for (const auto& f : frames) builder.Push(f);
  builder.Finish();
  EXPECT_GT(builder.stats().readbacks, 0);
  auto [id, px] = TileAt(0, 0);
  cv::Mat tile = WithColourChannels(DecodeTile(*store->GetTile(id)), 3);
  EXPECT_NEAR(tile.at<cv::Vec4b>(px)[1], 150, 3);
}

TEST_F(MosaicBuilderTest, PaintsFromThePhotoItIsHandedDecoded) {
  // The online navigation filter decoded the photo already: the builder
  // paints from those pixels and does not read the file again.
  auto store = OpenTileStore((dir_ / "m.mbtiles").string(), "png", true);
  std::vector<FrameSpec> frames{Frame(0, 0, 0, 100)};
  MosaicPlan plan = PlanMosaic(config_.map, camera_, frame_, frames, 1);
  MosaicBuilder builder(config_, camera_, frame_, plan, store.get());
  builder.Push(frames[0], cv::Mat(camera_.height, camera_.width, CV_8UC1, cv::Scalar(40)));
  builder.Finish();
  EXPECT_EQ(builder.stats().frames_used, 1);
  auto [id, px] = TileAt(0, 0);
  EXPECT_NEAR(DecodeTile(*store->GetTile(id)).at<cv::Vec2b>(px)[0], 40, 1);
}

TEST_F(MosaicBuilderTest, ReadsAColourJpegForAGrayMapItselfEvenWhenHandedItDecoded) {
  // libjpeg's luma, not OpenCV's colour conversion: the map stays what it was.
  const std::string path = (dir_ / "c.jpg").string();
  cv::imwrite(path, cv::Mat(camera_.height, camera_.width, CV_8UC3, cv::Scalar(100, 100, 100)));
  FrameSpec f = Frame(0, 0, 0, 0);
  f.image_path = path;
  auto store = OpenTileStore((dir_ / "m.mbtiles").string(), "png", true);
  MosaicPlan plan = PlanMosaic(config_.map, camera_, frame_, {f}, 1);
  MosaicBuilder builder(config_, camera_, frame_, plan, store.get());
  builder.Push(f, cv::Mat(camera_.height, camera_.width, CV_8UC3, cv::Scalar(40, 40, 40)));
  builder.Finish();
  auto [id, px] = TileAt(0, 0);
  EXPECT_NEAR(DecodeTile(*store->GetTile(id)).at<cv::Vec2b>(px)[0], 100, 2);
}

TEST(UsesDecodedTest, OnlyWhereTheDecodedPixelsAreThoseTheMapWouldRead) {
  ImageHeader png{"png", 160, 120, 3, 1000};
  const cv::Mat colour(120, 160, CV_8UC3), gray(120, 160, CV_8UC1);
  EXPECT_TRUE(UsesDecoded(png, colour, 1));
  EXPECT_TRUE(UsesDecoded(png, gray, 3));
  EXPECT_FALSE(UsesDecoded(png, cv::Mat(), 1));
  EXPECT_FALSE(UsesDecoded(png, cv::Mat(60, 80, CV_8UC3), 3));  // not the photo the header describes
  ImageHeader jpeg{"jpeg", 160, 120, 3, 1000};
  EXPECT_TRUE(UsesDecoded(jpeg, colour, 3));
  EXPECT_TRUE(UsesDecoded(jpeg, gray, 1));
  EXPECT_FALSE(UsesDecoded(jpeg, colour, 1));  // libjpeg's luma differs from OpenCV's gray
  EXPECT_FALSE(UsesDecoded(jpeg, gray, 3));
  ImageHeader unknown{"", 0, 0, 0, 1000};  // decoded to learn its size: read by the pipeline
  EXPECT_FALSE(UsesDecoded(unknown, colour, 3));
}

TEST(UsesDecodedTest, AJpegItUsesDecodesAsTheRowDecoderDoes) {
  testing::TempDir dir;
  cv::Mat noise(120, 160, CV_8UC3);
  cv::randu(noise, 0, 255);
  for (int channels : {1, 3}) {
    const std::string path = (dir / ("f" + std::to_string(channels) + ".jpg")).string();
    cv::Mat photo = noise;
    if (channels == 1) cv::extractChannel(noise, photo, 1);
    ASSERT_TRUE(cv::imwrite(path, photo));
    const cv::Mat decoded = cv::imread(path, cv::IMREAD_UNCHANGED);
    std::string problem;
    const auto header = ReadImageHeader(path, &problem);
    ASSERT_TRUE(header) << problem;
    ASSERT_TRUE(UsesDecoded(*header, decoded, channels));
    auto rows = FrameImage::Read(path, channels, 65535, &problem);
    ASSERT_TRUE(rows) << problem;
    FrameImage handed = FrameImage::FromMat(decoded, channels, 65535);
    EXPECT_EQ(cv::norm(rows->Full(), handed.Full(), cv::NORM_INF), 0) << channels << " channels";
  }
}

TEST_F(MosaicBuilderTest, TileIsWrittenOnceTheFrameMovesOn) {
  auto store = OpenTileStore((dir_ / "m.mbtiles").string(), "png", true);
  std::vector<FrameSpec> frames{Frame(0, 0, 0, 90), Frame(1, 10, 0, 90)};
  MosaicPlan plan = PlanMosaic(config_.map, camera_, frame_, frames, 1);
  MosaicBuilder builder(config_, camera_, frame_, plan, store.get());
  builder.Push(frames[0]);
  builder.Push(frames[1]);
  auto [id, px] = TileAt(0, 0);
  // Pushes are pipelined; Finish drains them. Before that, nothing forces
  // frame 0's tiles out except frame 1 missing them.
  builder.Finish();
  EXPECT_TRUE(store->GetTile(id));
  EXPECT_EQ(builder.stats().readbacks, 0);
}

TEST_F(MosaicBuilderTest, LiveTilesAreWrittenEarlyButTheMapEndsTheSame) {
  // A slow pass: tiles stay in the buffer for several frames.
  std::vector<FrameSpec> frames;
  for (int i = 0; i < 12; ++i) frames.push_back(Frame(i, 0.05 * i, 0, static_cast<uint8_t>(60 + 10 * i)));
  auto build = [&](bool live, const std::string& name) {
    BuildConfig config = config_;
    config.buffer.live_tiles = live;
    config.buffer.batch_frames = 1;
    config.buffer.batch_seconds = 0;
    return BuildMap(config, frames, name);
  };
  auto [plain, plain_stats] = build(false, "plain.mbtiles");
  auto [live, live_stats] = build(true, "live.mbtiles");
  EXPECT_GT(live_stats.tiles_written, plain_stats.tiles_written);  // unfinished tiles went out too
  auto ids = plain->TileIds();
  ASSERT_FALSE(ids.empty());
  EXPECT_EQ(live->TileIds().size(), ids.size());
  for (const TileId& id : ids) {
    auto a = plain->GetTile(id), b = live->GetTile(id);
    ASSERT_TRUE(a && b) << id.z << "/" << id.x << "/" << id.y;
    EXPECT_TRUE(*a == *b) << "tile " << id.z << "/" << id.x << "/" << id.y << " differs";
  }
}

// Two overlapping survey lines (there and back) of textured frames at 10x
// overlap, with navigation jitter.
std::vector<FrameSpec> TwoLines(const CameraModel& camera_, const std::filesystem::path& dir_,
                                const std::string& extension = ".png") {
  std::vector<FrameSpec> frames;
  cv::RNG rng(7);
  const double step = camera_.height * 2.0 / camera_.fy / 10, spacing = camera_.width * 2.0 / camera_.fx * 0.6;
  for (int i = 0; i < 80; ++i) {
    const bool back = i >= 40;
    const std::string path = (dir_ / ("t" + std::to_string(i) + extension)).string();
    cv::Mat texture(camera_.height, camera_.width, CV_8U);
    rng.fill(texture, cv::RNG::UNIFORM, 40, 220);
    cv::imwrite(path, texture);
    FrameSpec f;
    f.index = i;
    f.image = path;
    f.image_path = path;
    f.pose.east_m = back ? spacing : 0;
    f.pose.north_m = step * (back ? 79 - i : i);
    f.pose.heading_deg = back ? 180 : 0;
    // Jitter between frames, as navigation noise makes it: frames' edges
    // do not line up, so a frame alone sees slivers along its edge.
    f.pose.roll_deg = rng.uniform(-1.0, 1.0);
    f.pose.heading_deg += rng.uniform(-2.0, 2.0);
    f.pose.east_m += rng.uniform(-0.005, 0.005);
    f.pose.altitude_m = 2.0;
    frames.push_back(f);
  }
  return frames;
}

TEST_F(MosaicBuilderTest, ASecondLineBlendsAsIfTheFirstHadStayedInMemory) {
  // Built with tiles finished between the lines (and read back) and with
  // every tile kept in RAM, the maps agree to rounding: the read-back tiles
  // bring their weights. Every pixel a frame covers is painted (no handover
  // holes).
  const std::vector<FrameSpec> frames = TwoLines(camera_, dir_.path());
  auto build = [&](int linger, const std::string& name) {
    BuildConfig config = config_;
    config.buffer.linger_frames = linger;
    return BuildMap(config, frames, name);
  };
  auto [read_back, read_back_stats] = build(1, "read_back.mbtiles");
  auto [in_memory, in_memory_stats] = build(1000, "in_memory.mbtiles");
  EXPECT_GT(read_back_stats.readbacks, 0);
  EXPECT_EQ(in_memory_stats.readbacks, 0);
  int compared = 0;
  for (const TileId& id : in_memory->TileIds()) {
    if (id.z != 25) continue;
    cv::Mat a = DecodeTile(*in_memory->GetTile(id)), b = DecodeTile(*read_back->GetTile(id));
    std::vector<cv::Mat> ca, cb;
    cv::split(a, ca);
    cv::split(b, cb);
    EXPECT_EQ(cv::norm(ca[1], cb[1], cv::NORM_INF), 0) << "coverage differs";
    EXPECT_LE(cv::norm(ca[0], cb[0], cv::NORM_INF), 2) << "tile " << id.x << "/" << id.y;
    ++compared;
  }
  EXPECT_GT(compared, 4);

  // Coverage equals the union of the frames' footprints (all frames blended
  // everywhere paints exactly that).
  BuildConfig all = config_;
  all.blend.blend_all_overlaps = true;
  auto every = BuildMap(all, frames, "all.mbtiles").first;
  int64_t covered_all = 0, covered_handover = 0;
  for (const TileId& id : every->TileIds()) {
    if (id.z != 25) continue;
    std::vector<cv::Mat> ca, cb;
    cv::split(DecodeTile(*every->GetTile(id)), ca);
    auto mine = read_back->GetTile(id);
    ASSERT_TRUE(mine) << "tile " << id.x << "/" << id.y << " missing";
    cv::split(DecodeTile(*mine), cb);
    covered_all += cv::countNonZero(ca[1]);
    covered_handover += cv::countNonZero(cb[1]);
    EXPECT_EQ(cv::countNonZero(ca[1] & ~cb[1]), 0) << "holes in tile " << id.x << "/" << id.y;
  }
  EXPECT_EQ(covered_handover, covered_all);
}

TEST_F(MosaicBuilderTest, ForeseenSurveyWritesEachTileOnceAndTheSameMap) {
  // Told the whole survey, the builder keeps the first line's tiles until the
  // second line has passed them: nothing is read back, every tile is written
  // once, and the map is the one built by reading tiles back.
  const std::vector<FrameSpec> frames = TwoLines(camera_, dir_.path());
  BuildConfig config = config_;
  config.buffer.batch_seconds = 1e6;  // overviews written once, at the end, however slow the machine
  auto [read_back, read_back_stats] = BuildMap(config, frames, "read_back.mbtiles");
  auto [foreseen, foreseen_stats] = BuildMap(config, frames, "foreseen.mbtiles", true);
  EXPECT_GT(read_back_stats.readbacks, 0);
  EXPECT_EQ(foreseen_stats.readbacks, 0);
  int64_t distinct = 0;
  for (const auto& [zoom, count] : foreseen_stats.tiles_per_zoom) distinct += count;
  EXPECT_EQ(foreseen_stats.tiles_written, distinct);
  EXPECT_GT(read_back_stats.tiles_written, distinct);
  const auto ids = foreseen->TileIds();
  EXPECT_EQ(ids.size(), read_back->TileIds().size());
  for (const TileId& id : ids) {
    auto other = read_back->GetTile(id);
    ASSERT_TRUE(other) << "tile " << id.z << "/" << id.x << "/" << id.y;
    std::vector<cv::Mat> ca, cb;
    cv::split(DecodeTile(*foreseen->GetTile(id)), ca);
    cv::split(DecodeTile(*other), cb);
    EXPECT_EQ(cv::norm(ca[1], cb[1], cv::NORM_INF), 0) << "coverage differs";
    EXPECT_LE(cv::norm(ca[0], cb[0], cv::NORM_INF), 2) << "tile " << id.z << "/" << id.x << "/" << id.y;
  }

  // lookahead_frames 0 turns it off; a look-ahead shorter than the way back
  // along the line keeps only the tiles revisited soon enough.
  BuildConfig off = config, short_look = config;
  off.buffer.lookahead_frames = 0;
  short_look.buffer.lookahead_frames = 10;
  EXPECT_EQ(BuildMap(off, frames, "off.mbtiles", true).second.readbacks, read_back_stats.readbacks);
  const int64_t short_readbacks = BuildMap(short_look, frames, "short.mbtiles", true).second.readbacks;
  EXPECT_GT(short_readbacks, 0);
  EXPECT_LT(short_readbacks, read_back_stats.readbacks);
}

TEST_F(MosaicBuilderTest, TheMapDoesNotDependOnThreads) {
  // JPEG frames (decoded by rows) on two lines, the survey told to the
  // builder: one thread or eight give the same bytes.
  std::vector<FrameSpec> frames = TwoLines(camera_, dir_.path(), ".jpg");
  BuildConfig one = config_, eight = config_;
  one.threads = 1;
  eight.threads = 8;
  auto [a, a_stats] = BuildMap(one, frames, "one.mbtiles", true);
  auto b = BuildMap(eight, frames, "eight.mbtiles", true).first;
  EXPECT_EQ(a_stats.frames_used, 80);
  ASSERT_EQ(a->TileIds(), b->TileIds());
  for (const TileId& id : a->TileIds())
    EXPECT_EQ(*a->GetTile(id), *b->GetTile(id)) << id.z << "/" << id.x << "/" << id.y;
}

TEST_F(MosaicBuilderTest, TileConsumersGetEveryTileTheStoreGets) {
  // A consumer sees each tile as it is written, with the pixels the store
  // holds; only finished tiles are final.
  struct Recorder : TileConsumer {
    std::mutex mutex;
    std::map<TileId, cv::Mat> final_tiles;
    int live = 0;
    void OnTileWritten(const TileId& id, const cv::Mat& tile, uint64_t, bool final) override {
      std::lock_guard<std::mutex> lock(mutex);
      if (final)
        final_tiles[id] = tile.clone();
      else
        ++live;
    }
  } recorder;
  std::vector<FrameSpec> frames = TwoLines(camera_, dir_.path(), ".png");
  BuildConfig live = config_;
  live.buffer.live_tiles = true;
  live.buffer.batch_frames = 5;
  live.buffer.batch_seconds = 0;
  auto store = OpenTileStore((dir_ / "consumed.mbtiles").string(), "png", true);
  MosaicPlan plan = PlanMosaic(live.map, camera_, frame_, frames, 1);
  BuildHooks hooks;
  hooks.tile_consumers = {&recorder};
  MosaicBuilder builder(live, camera_, frame_, plan, store.get(), hooks);
  for (const auto& f : frames) builder.Push(f);
  builder.Finish();
  EXPECT_GT(recorder.live, 0);
  ASSERT_EQ(recorder.final_tiles.size(), store->TileIds().size());
  for (const auto& [id, tile] : recorder.final_tiles) {
    const cv::Mat stored = DecodeTile(*store->GetTile(id));
    EXPECT_EQ(cv::norm(WithColourChannels(stored, 1), tile, cv::NORM_INF), 0) << id.z << "/" << id.x << "/" << id.y;
  }
}

TEST_F(MosaicBuilderTest, MissingImageIsRejectedAndRecorded) {
  auto store = OpenTileStore((dir_ / "m.mbtiles").string(), "png", true);
  FrameSpec missing = Frame(0, 0, 0, 10);
  missing.image_path = (dir_ / "nope.png").string();
  std::vector<FrameSpec> frames{missing, Frame(1, 0, 0, 90)};
  MosaicPlan plan = PlanMosaic(config_.map, camera_, frame_, frames, 1);
  MosaicBuilder builder(config_, camera_, frame_, plan, store.get());
  for (const auto& f : frames) builder.Push(f);
  builder.Finish();
  ASSERT_EQ(builder.stats().rejections.size(), 1u);
  EXPECT_EQ(builder.stats().rejections[0].reason, "missing image");
  EXPECT_EQ(store->Records().Frames().size(), 2u);
  EXPECT_EQ(store->Records().Frames()[0].status, "missing image");
}

TEST_F(MosaicBuilderTest, SteepAttitudeIsRejected) {
  auto store = OpenTileStore((dir_ / "m.mbtiles").string(), "png", true);
  FrameSpec steep = Frame(0, 0, 0, 10);
  steep.pose.pitch_deg = 80;
  std::vector<FrameSpec> frames{steep, Frame(1, 0, 0, 90)};
  MosaicPlan plan = PlanMosaic(config_.map, camera_, frame_, frames, 1);
  MosaicBuilder builder(config_, camera_, frame_, plan, store.get());
  for (const auto& f : frames) builder.Push(f);
  builder.Finish();
  ASSERT_EQ(builder.stats().rejections.size(), 1u);
  EXPECT_EQ(builder.stats().rejections[0].field, "pitch_deg/roll_deg");
  EXPECT_EQ(builder.stats().frames_used, 1);
}

TEST(PlanMosaic, ZoomsFollowTheGroundSampleDistance) {
  CameraModel camera = CameraFromFocalLength(8, 12.9, 696, 520);
  LocalFrame frame({43.1, 131.9});
  std::vector<FrameSpec> frames(2);
  frames[0].pose.altitude_m = frames[1].pose.altitude_m = 1.8;
  frames[1].pose.east_m = 50;
  MosaicPlan plan = PlanMosaic(MapSettings{}, camera, frame, frames, 1);
  EXPECT_NEAR(plan.gsd_m, 1.8 / 620.155, 1e-6);
  EXPECT_EQ(plan.base_zoom, 25);
  // 50 m plus a footprint (52.5 m) fits one tile at zoom 19 (a tile is
  // 40075 km * cos(43.1) / 2^19 = 55.8 m wide) but not at 20 (27.9 m).
  EXPECT_EQ(plan.min_zoom, 19);
}

}  // namespace
}  // namespace seamap
