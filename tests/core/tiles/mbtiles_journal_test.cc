// Checkpoints in an MBTiles file: a rollback returns tiles, frames and track
// to the last checkpoint, each layer on its own; the checkpoint and its
// blobs read back, also read-only.
#include <gtest/gtest.h>

#include <stdexcept>

#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using Bytes = std::vector<uint8_t>;

FrameRecord Frame(int id) {
  FrameRecord f;
  f.id = id;
  f.image = "f" + std::to_string(id);
  return f;
}

TrackPoint Point(int seq) {
  TrackPoint p;
  p.seq = seq;
  return p;
}

CheckpointUpdate Update(const std::string& progress, int64_t frames_from, int64_t track_from) {
  CheckpointUpdate u;
  u.progress = progress;
  u.frames_from = frames_from;
  u.track_from = track_from;
  return u;
}

TEST(MBTilesJournal, RollBackReturnsTilesFramesAndTrackToTheCheckpoint) {
  testing::TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  {
    MBTilesStore store(path);
    store.PutTile({5, 1, 1}, {1});  // before any checkpoint: not journaled
    store.PutFrame(Frame(0));
    store.PutTrackPoint(Point(0));
    CheckpointUpdate first = Update("{\"n\":1}", 1, 1);
    first.put.push_back({0, {5, 1, 1}, {7, 7}});
    store.WriteCheckpoint(first);

    store.PutTile({5, 1, 1}, {2});  // replaced, then replaced again
    store.PutTile({5, 1, 1}, {3});
    store.PutTile({5, 2, 2}, {4});  // new
    store.PutFrame(Frame(1));
    store.PutTrackPoint(Point(1));
    store.Flush();  // committed: the journal travels with the writes
  }
  MBTilesStore store(path);
  EXPECT_EQ(*store.GetTile({5, 1, 1}), Bytes{3});
  store.RollBackToCheckpoint();
  EXPECT_EQ(*store.GetTile({5, 1, 1}), Bytes{1});
  EXPECT_FALSE(store.GetTile({5, 2, 2}));
  ASSERT_EQ(store.Frames().size(), 1u);
  ASSERT_EQ(store.Track().size(), 1u);
  ASSERT_TRUE(store.ReadCheckpoint());
  EXPECT_EQ(store.ReadCheckpoint()->progress, "{\"n\":1}");
  EXPECT_EQ(*store.ReadCheckpointBlob(0, {5, 1, 1}), (Bytes{7, 7}));
  EXPECT_FALSE(store.ReadCheckpointBlob(1, {5, 1, 1}));

  // A later checkpoint keeps what came before it, drops a blob, and rolls back to itself.
  store.PutTile({5, 3, 3}, {5});
  CheckpointUpdate second = Update("{\"n\":2}", 1, 1);
  second.drop.push_back({0, {5, 1, 1}});
  store.WriteCheckpoint(second);
  store.PutTile({5, 3, 3}, {6});
  store.RollBackToCheckpoint();
  EXPECT_EQ(*store.GetTile({5, 3, 3}), Bytes{5});
  EXPECT_FALSE(store.ReadCheckpointBlob(0, {5, 1, 1}));

  MBTilesStore reader(path, MBTilesStore::Mode::kReadOnly);
  EXPECT_EQ(reader.ReadCheckpoint()->progress, "{\"n\":2}");
  // Read-only, it reads its checkpoints but writes none.
  EXPECT_THROW(reader.WriteCheckpoint(Update("{\"n\":3}", 2, 2)), std::runtime_error);
  EXPECT_THROW(reader.DropCheckpoint(), std::runtime_error);
}

TEST(MBTilesJournal, LayersHaveTheirOwnCheckpointsAndOnlyTheMainOneOwnsFrames) {
  testing::TempDir dir;
  MBTilesStore store((dir / "m.mbtiles").string());
  auto layer_store = store.OpenLayer("enhanced");
  CheckpointStore* layer = layer_store->Checkpoints();
  ASSERT_NE(layer, nullptr);
  store.WriteCheckpoint(Update("main", 0, 0));
  layer->WriteCheckpoint(Update("layer", 0, 0));
  store.PutTile({4, 0, 0}, {1});
  layer_store->PutTile({4, 0, 0}, {2});
  store.PutFrame(Frame(0));
  layer->RollBackToCheckpoint();
  EXPECT_FALSE(layer_store->GetTile({4, 0, 0}));
  EXPECT_EQ(*store.GetTile({4, 0, 0}), Bytes{1});
  EXPECT_EQ(store.Frames().size(), 1u);
  EXPECT_EQ(layer->ReadCheckpoint()->progress, "layer");
  store.RollBackToCheckpoint();
  EXPECT_FALSE(store.GetTile({4, 0, 0}));
  EXPECT_TRUE(store.Frames().empty());
}

TEST(MBTilesJournal, DroppedCheckpointStopsTheJournal) {
  testing::TempDir dir;
  MBTilesStore store((dir / "m.mbtiles").string());
  store.WriteCheckpoint(Update("x", -1, -1));
  store.PutTile({4, 0, 0}, {1});
  store.DropCheckpoint();
  store.Flush();
  EXPECT_FALSE(store.ReadCheckpoint());
  store.PutTile({4, 0, 0}, {2});
  store.RollBackToCheckpoint();  // none: nothing happens
  EXPECT_EQ(*store.GetTile({4, 0, 0}), Bytes{2});
}

TEST(MBTilesJournal, AMapWithoutCheckpointTablesHasNone) {
  testing::TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  { MBTilesStore store(path); }
  MBTilesStore reader(path, MBTilesStore::Mode::kReadOnly);
  EXPECT_FALSE(reader.ReadCheckpoint());
  EXPECT_FALSE(reader.ReadCheckpointBlob(0, {1, 0, 0}));
}

}  // namespace
}  // namespace seamap
