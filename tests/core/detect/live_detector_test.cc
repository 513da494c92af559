#include "core/detect/live_detector.h"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <set>
#include <thread>

#include "core/tiles/tile_codec.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

const std::string kFixtures = std::string(SEAMAP_SOURCE_DIR) + "/tests/fixtures/";

// A real folder store that remembers every tile read back, to prove the
// detector composes windows from final tiles only.
class RecordingStore : public TileStore {
 public:
  explicit RecordingStore(std::unique_ptr<TileStore> inner) : inner_(std::move(inner)) {}
  void PutTile(const TileId& id, const std::vector<uint8_t>& bytes) override { inner_->PutTile(id, bytes); }
  std::optional<std::vector<uint8_t>> GetTile(const TileId& id) const override {
    auto bytes = inner_->GetTile(id);
    std::lock_guard<std::mutex> lock(mutex_);
    if (bytes) reads_.push_back(*bytes);
    return bytes;
  }
  int64_t TileCount() const override { return inner_->TileCount(); }
  std::vector<TileId> TileIds() const override { return inner_->TileIds(); }
  void SetMetadata(const std::string& k, const std::string& v) override { inner_->SetMetadata(k, v); }
  std::map<std::string, std::string> Metadata() const override { return inner_->Metadata(); }
  void Flush() override { inner_->Flush(); }
  std::unique_ptr<TileStore> OpenLayer(const std::string& name) override { return inner_->OpenLayer(name); }

  std::vector<std::vector<uint8_t>> reads() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return reads_;
  }

 private:
  MissionRecords& RecordsKept() override { return inner_->Records(); }
  CheckpointStore* CheckpointsKept() override { return nullptr; }

  std::unique_ptr<TileStore> inner_;
  mutable std::mutex mutex_;
  mutable std::vector<std::vector<uint8_t>> reads_;
};

cv::Mat Tile(int gray) {
  return cv::Mat(256, 256, CV_8UC2, cv::Scalar(gray, 255));
}

TEST(LiveDetector, ComposesWindowsFromFinalTilesOnlyAndSearchesChangedOnesAtTheEnd) {
  testing::TempDir dir;
  RecordingStore store(OpenTileStore((dir / "map").string(), "png", true));
  DetectSettings s;
  s.model = YoloModel::Inspect(kFixtures + "yolo_v8_fixture.onnx", "");
  s.zooms = {20};
  s.origin = PixelToLatLon({1000.5 * 256, 3000.5 * 256}, 20, 256);
  LiveDetector detector(s, &store);
  const TileEncoding png;
  const auto put = [&](const TileId& id, const cv::Mat& tile, bool final) {
    store.PutTile(id, EncodeTile(tile, png));
    detector.OnTileWritten(id, tile, 0, final);
  };
  std::set<std::vector<uint8_t>> final_bytes;
  // A half-painted live tile: its windows wait for it.
  put({20, 1001, 3001}, Tile(50), false);
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));
  EXPECT_TRUE(store.reads().empty());
  EXPECT_EQ(detector.stats().searched, 0);
  // Finished: its four windows become due (and the tile is final when read).
  put({20, 1001, 3001}, Tile(60), true);
  final_bytes.insert(EncodeTile(Tile(60), png));
  // A neighbour finished, then finished again with new pixels.
  put({20, 1002, 3001}, Tile(70), true);
  put({20, 1002, 3001}, Tile(80), true);
  final_bytes.insert(EncodeTile(Tile(80), png));
  const auto objects = detector.Finish({});
  for (const auto& bytes : store.reads()) EXPECT_TRUE(final_bytes.count(bytes)) << "a window read a tile not final";
  // Two windows hold these tiles (x 1000 and 1002, y 3000); each searched at least once.
  EXPECT_GE(detector.stats().searched, 2);
  EXPECT_EQ(detector.stats().skipped, 0);
  EXPECT_FALSE(objects.empty());
  EXPECT_EQ(objects[0].model, s.model->name);
}

}  // namespace
}  // namespace seamap
