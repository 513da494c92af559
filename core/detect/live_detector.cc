#include "core/detect/live_detector.h"

#include <algorithm>

#include "core/detect/search_levels.h"

namespace seamap {
namespace {
// A window waits this long after its last change: tiles finished together
// (a survey line) then cost one search, not one per tile.
constexpr auto kSettle = std::chrono::milliseconds(500);
}  // namespace

LiveDetector::LiveDetector(const DetectSettings& settings, const TileStore* store)
    : settings_(settings), store_(store), searcher_(settings), worker_([this] { Work(); }) {}

LiveDetector::~LiveDetector() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void LiveDetector::OnTileWritten(const TileId& id, const cv::Mat&, uint64_t, bool final) {
  const auto searched = [&](int z) {
    return std::find(settings_.zooms.begin(), settings_.zooms.end(), z) != settings_.zooms.end();
  };
  // A stored tile below a searched level one zoom up changes that level's four tiles (cut from it).
  std::vector<TileId> changed;
  if (searched(id.z)) changed.push_back(id);
  if (id.z == settings_.stored_zoom && searched(id.z + 1))
    for (const TileId& c : ChildTiles(id)) changed.push_back(c);
  if (changed.empty()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    for (const TileId& t : changed) {
      if (final)
        live_.erase(t);
      else
        live_.insert(t);
      for (const WindowKey& w : WindowsHolding(t, WindowTiles(settings_.tile_size))) dirty_[w] = now;
    }
    backlog_peak_ = std::max(backlog_peak_, static_cast<int>(dirty_.size()));
  }
  wake_.notify_one();
}

void LiveDetector::OnFound(Found found, std::function<std::vector<FrameRecord>()> frames,
                           std::chrono::milliseconds every) {
  std::lock_guard<std::mutex> lock(mutex_);
  found_ = std::move(found);
  frames_ = std::move(frames);
  every_ = every;
}

bool LiveDetector::Due(const WindowKey& w) const {
  if (finishing_) return true;
  const int n = WindowTiles(settings_.tile_size);
  for (int dy = 0; dy < n; ++dy)
    for (int dx = 0; dx < n; ++dx)
      if (live_.count({w.z, w.x + dx, w.y + dy})) return false;
  return std::chrono::steady_clock::now() - dirty_.at(w) >= kSettle;
}

void LiveDetector::Work() {
  const TileReader read = StoreReader(*store_, settings_.stored_zoom);
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    auto it = std::find_if(dirty_.begin(), dirty_.end(), [&](const auto& d) { return Due(d.first); });
    if (it == dirty_.end()) {
      if (finishing_) break;  // drained
      wake_.wait_for(lock, kSettle);
      continue;
    }
    const WindowKey w = it->first;
    dirty_.erase(it);  // before reading: a tile changing during the search makes it due again
    lock.unlock();
    try {
      searcher_.Search(w, read);
    } catch (...) {
      lock.lock();
      error_ = std::current_exception();
      break;
    }
    lock.lock();
    const auto now = std::chrono::steady_clock::now();
    if (found_ && !finishing_ && now - last_found_ >= every_) {
      last_found_ = now;
      const Found found = found_;
      const auto frames = frames_;
      lock.unlock();
      try {
        found(searcher_.Objects(frames()));
      } catch (...) {
        lock.lock();
        error_ = std::current_exception();
        break;
      }
      lock.lock();
    }
  }
}

std::vector<RecognisedObject> LiveDetector::Finish(const std::vector<FrameRecord>& frames) {
  const auto t0 = std::chrono::steady_clock::now();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    finishing_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
  if (error_) std::rethrow_exception(error_);
  // Windows no tile of this run touched (the worker has stopped: no locks needed).
  const TileReader read = StoreReader(*store_, settings_.stored_zoom);
  for (const WindowKey& w : MapWindows(*store_, settings_.zooms, settings_.tile_size, settings_.stored_zoom))
    if (!searcher_.Searched(w)) searcher_.Search(w, read);
  drain_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (error_) std::rethrow_exception(error_);
  return searcher_.Objects(frames);
}

}  // namespace seamap
