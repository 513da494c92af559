#include "core/nav/frame_feed.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using testing::TempDir;

FrameList ThreeFrames() {
  FrameList list;
  for (int i = 0; i < 3; ++i) {
    FrameSpec f;
    f.index = i;
    f.image = "f" + std::to_string(i) + ".png";
    f.time_s = 10.0 + 0.2 * i;
    list.frames.push_back(f);
  }
  list.rejected.push_back({"nav.csv", 7, "altitude_m", "must be > 0"});
  return list;
}

TEST(RecordedFeed, HandsOutRejectionsThenFramesInOrder) {
  RecordedFeed feed(ThreeFrames(), /*speed=*/0);
  EXPECT_EQ(feed.Total(), 4);
  auto first = feed.Next();
  ASSERT_TRUE(first && first->rejection);
  EXPECT_EQ(first->rejection->line, 7);
  for (int i = 0; i < 3; ++i) {
    auto item = feed.Next();
    ASSERT_TRUE(item && item->frame);
    EXPECT_EQ(item->frame->index, i);
  }
  EXPECT_FALSE(feed.Next());
}

TEST(RecordedFeed, KeepsTheRecordedPaceScaledBySpeed) {
  // 0.4 s of recording at 2x: the last frame comes no earlier than 0.2 s after the first.
  RecordedFeed feed(ThreeFrames(), /*speed=*/2);
  feed.Next();  // the rejection
  const auto start = Clock::now();
  feed.Next();
  feed.Next();
  feed.Next();
  EXPECT_GE(std::chrono::duration<double>(Clock::now() - start).count(), 0.19);
}

TEST(RecordedFeed, StopEndsAWait) {
  FrameList list = ThreeFrames();
  list.frames[2].time_s = 10000;  // hours away
  RecordedFeed feed(list, 1);
  feed.Next();
  feed.Next();
  feed.Next();
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    feed.Stop();
  });
  EXPECT_FALSE(feed.Next());
  stopper.join();
}

TEST(FolderWatchFeed, TakesFramesAsLinesAndPhotosAppearAndSkipsLostPhotos) {
  TempDir dir;
  fs::create_directories(dir / "photo");
  const fs::path nav = dir / "nav.csv";
  NavReadOptions options;
  options.origin = LatLon{43.1, 131.9};
  FolderWatchFeed feed(nav.string(), (dir / "photo").string(), options, /*idle_timeout_s=*/1.0,
                       /*image_wait_s=*/0.3, /*poll_ms=*/20);
  std::thread diver([&] {
    std::ofstream out(nav);
    out << "image,time_s,x_m,y_m,altitude_m,heading_deg\n" << std::flush;
    for (int i = 0; i < 4; ++i) {
      const std::string name = "f" + std::to_string(i) + ".png";
      if (i != 1) std::ofstream(dir / "photo" / name) << "photo bytes";  // photo 1 is lost
      out << name << "," << i * 0.2;
      if (i == 3) {  // half a line stays unread until it is complete
        out << std::flush;
        std::this_thread::sleep_for(std::chrono::milliseconds(80));
      }
      out << "," << i * 0.1 << ",0,1.8,0\n" << std::flush;
      std::this_thread::sleep_for(std::chrono::milliseconds(60));
    }
  });
  std::vector<std::string> frames, rejected;
  while (auto item = feed.Next()) {
    if (item->frame) frames.push_back(item->frame->image);
    if (item->rejection) rejected.push_back(item->rejection->field + ": " + item->rejection->reason);
  }
  diver.join();
  EXPECT_EQ(frames, (std::vector<std::string>{"f0.png", "f2.png", "f3.png"}));
  ASSERT_GE(rejected.size(), 1u);
  EXPECT_NE(rejected[0].find("image: photo did not appear"), std::string::npos) << rejected[0];
}

TEST(FolderWatchFeed, WaitsThroughAHeaderOnlyFileAndHandsEachPhotoOutOnce) {
  TempDir dir;
  const fs::path nav = dir / "nav.csv";
  NavReadOptions options;
  options.origin = LatLon{43.1, 131.9};
  std::ofstream(nav) << "image,time_s,x_m,y_m,altitude_m\n";
  std::ofstream(dir / "a.png") << "a";
  std::ofstream(dir / "b.png") << "b";
  FolderWatchFeed feed(nav.string(), dir.path().string(), options, /*idle_timeout_s=*/0.5, 10, /*poll_ms=*/20);
  std::thread diver([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::ofstream(nav, std::ios::app) << "b.png,2.0,0,0,1.8\n" << std::flush;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    // A line with an earlier time arrives later: it is still handed out, once, after b.
    std::ofstream(nav, std::ios::app) << "a.png,1.0,0,0,1.8\n" << std::flush;
  });
  std::vector<std::pair<std::string, int>> frames;
  while (auto item = feed.Next())
    if (item->frame) frames.push_back({item->frame->image, item->frame->index});
  diver.join();
  EXPECT_EQ(frames, (std::vector<std::pair<std::string, int>>{{"b.png", 0}, {"a.png", 1}}));
}

TEST(FolderWatchFeed, ErrorsNameTheWatchedFileNotItsCopy) {
  TempDir dir;
  const fs::path nav = dir / "nav.csv";
  std::ofstream(nav) << "no,known,columns\n1,2,3\n";
  FolderWatchFeed feed(nav.string(), dir.path().string(), NavReadOptions{}, 0.2, 10, 20);
  try {
    feed.Next();
    FAIL() << "an unreadable navigation file was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), nav.string());
  }
}

}  // namespace
}  // namespace seamap
