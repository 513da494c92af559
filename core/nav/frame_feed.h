#pragma once
// Where a live build gets its frames, one at a time: a recorded survey played
// back at its recorded pace (scaled), or a folder that fills up with photos
// and navigation lines during a dive. Both hand out frames in acquisition
// order; the builder does not know which it has.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/nav/frame_list.h"
#include "core/nav/nav_table.h"

namespace seamap {

struct FeedItem {
  std::optional<FrameSpec> frame;
  std::optional<Rejection> rejection;  // a frame that will never come (bad line, lost photo)
};

class FrameFeed {
 public:
  virtual ~FrameFeed() = default;
  // The next frame or rejection, waiting for it; nullopt when the feed has
  // ended or Stop() was called.
  virtual std::optional<FeedItem> Next() = 0;
  // Frames expected in all; 0 when unknown (a folder being filled).
  virtual int Total() const = 0;
  // Ends the feed; wakes a waiting Next(). Thread-safe.
  void Stop();
  bool stopped() const { return stop_; }

 protected:
  // Sleeps until `deadline` or Stop(); false when stopped.
  bool SleepUntil(std::chrono::steady_clock::time_point deadline);

 private:
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
};

// A recorded survey at `speed` times its recorded pace (0: as fast as the
// builder takes them). Frames without times are spaced at `rate_hz`.
class RecordedFeed : public FrameFeed {
 public:
  RecordedFeed(FrameList frames, double speed, double rate_hz = 5);
  std::optional<FeedItem> Next() override;
  int Total() const override { return static_cast<int>(list_.frames.size() + list_.rejected.size()); }

 private:
  FrameList list_;
  double speed_, rate_hz_;
  size_t next_rejection_ = 0, next_frame_ = 0;
  std::optional<std::chrono::steady_clock::time_point> start_;
  double first_time_ = 0;
};

// A folder being filled: the navigation file grows line by line and photos
// appear in `images_dir`. A frame is handed out when its navigation line is
// complete and its photo exists and has stopped growing; each photo and each
// rejected line once, in the order they first appear. A photo still
// missing `image_wait_s` after later frames' photos appeared is rejected.
// The feed ends after `idle_timeout_s` without anything new (0: never; Stop()).
class FolderWatchFeed : public FrameFeed {
 public:
  FolderWatchFeed(std::string nav_path, std::string images_dir, NavReadOptions options, double idle_timeout_s = 0,
                  double image_wait_s = 10, int poll_ms = 200);
  std::optional<FeedItem> Next() override;
  int Total() const override { return 0; }
  // Reads the navigation's complete lines now (the first read fixes the origin).
  NavTable ReadCompleteLines();

 private:
  void Poll();

  std::string nav_path_, images_dir_;
  NavReadOptions options_;
  double idle_timeout_s_, image_wait_s_;
  int poll_ms_;
  // What the navigation has named so far, each handed out once, in the order first seen.
  std::set<std::string> known_, reported_;
  std::deque<FrameSpec> pending_frames_;
  std::deque<Rejection> pending_rejections_;
  std::map<std::string, uintmax_t> sizes_;  // photo sizes at the last poll
  std::chrono::steady_clock::time_point last_news_;
  std::optional<std::chrono::steady_clock::time_point> waiting_since_;
  uintmax_t nav_size_ = 0;
  int next_index_ = 0;
};

}  // namespace seamap
