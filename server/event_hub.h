#pragma once
// Live events for Server-Sent Events streams: a bounded history, so a client
// that reconnects with Last-Event-ID gets what it missed, and a condition
// variable that wakes every waiting stream when something new arrives.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

namespace seamap::server {

struct Event {
  uint64_t id = 0;   // 1, 2, 3, ...
  std::string type;  // "tile", "pose", "track", "detection", "progress"
  std::string data;  // JSON, one line
};

// "id: N\nevent: TYPE\ndata: DATA\n\n"
std::string FormatEvent(const Event& event);

class EventHub {
 public:
  explicit EventHub(size_t keep = 4096) : keep_(keep) {}

  uint64_t Publish(std::string type, std::string data);
  // Events with id > after (from the oldest kept when the client fell
  // further behind), waiting up to `timeout` for one; empty on timeout.
  // After Close() it returns at once, with what is left to deliver.
  std::vector<Event> WaitAfter(uint64_t after, std::chrono::milliseconds timeout);
  uint64_t LastId() const;
  // Wakes and ends every stream (server shutdown).
  void Close();
  bool closed() const;

 private:
  size_t keep_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Event> events_;
  uint64_t last_id_ = 0;
  bool closed_ = false;
};

}  // namespace seamap::server
