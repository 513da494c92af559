#include "core/nav/frame_feed.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

#include "core/nav/nav_reader.h"

namespace seamap {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

void FrameFeed::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
}

bool FrameFeed::SleepUntil(Clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait_until(lock, deadline, [this] { return stop_.load(); });
  return !stop_;
}

RecordedFeed::RecordedFeed(FrameList frames, double speed, double rate_hz)
    : list_(std::move(frames)), speed_(speed), rate_hz_(rate_hz > 0 ? rate_hz : 5) {}

std::optional<FeedItem> RecordedFeed::Next() {
  if (stopped()) return std::nullopt;
  if (next_rejection_ < list_.rejected.size()) return FeedItem{std::nullopt, list_.rejected[next_rejection_++]};
  if (next_frame_ >= list_.frames.size()) return std::nullopt;
  const FrameSpec& f = list_.frames[next_frame_];
  const double t = f.time_s ? *f.time_s : next_frame_ / rate_hz_;
  if (!start_) {
    start_ = Clock::now();
    first_time_ = t;
  }
  if (speed_ > 0) {
    const auto due = *start_ + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(std::max(0.0, t - first_time_) / speed_));
    if (!SleepUntil(due)) return std::nullopt;
  }
  ++next_frame_;
  return FeedItem{f, std::nullopt};
}

FolderWatchFeed::FolderWatchFeed(std::string nav_path, std::string images_dir, NavReadOptions options,
                                 double idle_timeout_s, double image_wait_s, int poll_ms)
    : nav_path_(std::move(nav_path)),
      images_dir_(std::move(images_dir)),
      options_(std::move(options)),
      idle_timeout_s_(idle_timeout_s),
      image_wait_s_(image_wait_s),
      poll_ms_(poll_ms),
      last_news_(Clock::now()) {}

NavTable FolderWatchFeed::ReadCompleteLines() {
  // A line still being written would read as a bad row: read up to the last newline.
  std::ifstream in(nav_path_, std::ios::binary);
  std::string text(std::istreambuf_iterator<char>(in), {});
  text.resize(text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1);
  const fs::path copy = fs::temp_directory_path() / ("seamap-watch-" + std::to_string(::getpid()) + "-" +
                                                     fs::path(nav_path_).filename().string());
  {
    std::ofstream out(copy, std::ios::binary | std::ios::trunc);
    out << text;
  }
  NavTable nav;
  try {
    nav = ReadNavigation(copy.string(), options_);
  } catch (...) {
    std::error_code ec;
    fs::remove(copy, ec);
    throw;
  }
  std::error_code ec;
  fs::remove(copy, ec);
  nav.source = nav_path_;
  for (auto& r : nav.rejected) r.file = nav_path_;
  if (!options_.origin) options_.origin = nav.origin;  // later reads keep the first origin
  return nav;
}

void FolderWatchFeed::Poll() {
  std::error_code ec;
  const uintmax_t size = fs::exists(nav_path_, ec) ? fs::file_size(nav_path_, ec) : 0;
  if (size != nav_size_ && size > 0) {
    nav_size_ = size;
    NavTable nav = ReadCompleteLines();
    if (!nav.records.empty() || !nav.rejected.empty()) {
      FrameList list = MatchFrames(nav, images_dir_, std::nullopt);
      if (list.frames.size() > list_.frames.size() || list.rejected.size() > list_.rejected.size()) last_news_ = Clock::now();
      list.rejected.insert(list.rejected.begin(), nav.rejected.begin(), nav.rejected.end());
      list_ = std::move(list);
    }
  }
}

std::optional<FeedItem> FolderWatchFeed::Next() {
  while (!stopped()) {
    Poll();
    if (next_rejection_ < list_.rejected.size()) return FeedItem{std::nullopt, list_.rejected[next_rejection_++]};
    if (next_frame_ < list_.frames.size()) {
      const FrameSpec& f = list_.frames[next_frame_];
      std::error_code ec;
      const bool exists = fs::is_regular_file(f.image_path, ec);
      const uintmax_t size = exists ? fs::file_size(f.image_path, ec) : 0;
      auto previous = sizes_.find(f.image_path);
      if (exists && size > 0 && previous != sizes_.end() && previous->second == size) {
        sizes_.erase(previous);
        ++next_frame_;
        waiting_for_ = -1;
        last_news_ = Clock::now();
        return FeedItem{f, std::nullopt};
      }
      sizes_[f.image_path] = size;  // handed out once it has stopped growing
      if (waiting_for_ != static_cast<int>(next_frame_)) {
        waiting_for_ = static_cast<int>(next_frame_);
        waiting_since_ = Clock::now();
      } else if (!exists && next_frame_ + 1 < list_.frames.size() &&
                 Clock::now() - waiting_since_ > std::chrono::duration<double>(image_wait_s_)) {
        ++next_frame_;
        waiting_for_ = -1;
        return FeedItem{std::nullopt, Rejection{f.image_path, f.nav_line, "image",
                                                "photo did not appear within " + std::to_string(int(image_wait_s_)) +
                                                    " s while later photos did"}};
      }
    }
    if (idle_timeout_s_ > 0 && Clock::now() - last_news_ > std::chrono::duration<double>(idle_timeout_s_))
      return std::nullopt;
    if (!SleepUntil(Clock::now() + std::chrono::milliseconds(poll_ms_))) return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace seamap
