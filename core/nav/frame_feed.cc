#include "core/nav/frame_feed.h"

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/nav/nav_reader.h"
#include "core/util/error.h"

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
  const fs::path copy = fs::temp_directory_path() /
                        ("seamap-watch-" + std::to_string(::getpid()) + "-" + fs::path(nav_path_).filename().string());
  {
    std::ofstream out(copy, std::ios::binary | std::ios::trunc);
    out << text;
  }
  NavTable nav;
  std::error_code ec;
  try {
    nav = ReadNavigation(copy.string(), options_);
  } catch (const InputError& e) {
    fs::remove(copy, ec);
    // Errors name the watched file, not the private copy.
    throw InputError(e.file() == copy.string() ? nav_path_ : e.file(), e.line(), e.field(), e.detail());
  } catch (...) {
    fs::remove(copy, ec);
    throw;
  }
  fs::remove(copy, ec);
  nav.source = nav_path_;
  for (auto& r : nav.rejected)
    if (r.file == copy.string()) r.file = nav_path_;
  if (!options_.origin) options_.origin = nav.origin;  // later reads keep the first origin
  return nav;
}

void FolderWatchFeed::Poll() {
  std::error_code ec;
  const uintmax_t size = fs::exists(nav_path_, ec) ? fs::file_size(nav_path_, ec) : 0;
  if (size == nav_size_ || size == 0) return;
  nav_size_ = size;
  NavTable nav;
  try {
    nav = ReadCompleteLines();
  } catch (const InputError& e) {
    // A header without records yet (or a file being rewritten) is not an error while watching.
    if (e.detail().find("no navigation records") != std::string::npos) return;
    throw;
  }
  FrameList list = MatchFrames(nav, images_dir_, std::nullopt);
  list.rejected.insert(list.rejected.begin(), nav.rejected.begin(), nav.rejected.end());
  // Hand out each rejection once and each frame once, whatever the new list's order.
  for (const Rejection& r : list.rejected) {
    if (reported_.insert(r.Message()).second) {
      pending_rejections_.push_back(r);
      last_news_ = Clock::now();
    }
  }
  for (const FrameSpec& f : list.frames) {
    if (known_.insert(f.image_path).second) {
      pending_frames_.push_back(f);
      last_news_ = Clock::now();
    }
  }
}

std::optional<FeedItem> FolderWatchFeed::Next() {
  while (!stopped()) {
    Poll();
    if (!pending_rejections_.empty()) {
      Rejection r = pending_rejections_.front();
      pending_rejections_.pop_front();
      return FeedItem{std::nullopt, r};
    }
    if (!pending_frames_.empty()) {
      FrameSpec f = pending_frames_.front();
      std::error_code ec;
      const bool exists = fs::is_regular_file(f.image_path, ec);
      const uintmax_t size = exists ? fs::file_size(f.image_path, ec) : 0;
      auto previous = sizes_.find(f.image_path);
      if (exists && size > 0 && previous != sizes_.end() && previous->second == size) {
        sizes_.erase(previous);
        pending_frames_.pop_front();
        waiting_since_.reset();
        last_news_ = Clock::now();
        f.index = next_index_++;  // the order frames are handed out, whatever the file's later order
        return FeedItem{f, std::nullopt};
      }
      sizes_[f.image_path] = size;  // handed out once it has stopped growing
      if (!waiting_since_) waiting_since_ = Clock::now();
      if (!exists && pending_frames_.size() > 1 &&
          Clock::now() - *waiting_since_ > std::chrono::duration<double>(image_wait_s_)) {
        pending_frames_.pop_front();
        waiting_since_.reset();
        sizes_.erase(f.image_path);
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
