#include "server/event_hub.h"

namespace seamap::server {

std::string FormatEvent(const Event& e) {
  return "id: " + std::to_string(e.id) + "\nevent: " + e.type + "\ndata: " + e.data + "\n\n";
}

uint64_t EventHub::Publish(std::string type, std::string data) {
  uint64_t id;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    id = ++last_id_;
    events_.push_back({id, std::move(type), std::move(data)});
    while (events_.size() > keep_) events_.pop_front();
  }
  changed_.notify_all();
  return id;
}

std::vector<Event> EventHub::WaitAfter(uint64_t after, std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return closed_ || last_id_ > after; });
  std::vector<Event> out;
  for (const Event& e : events_)
    if (e.id > after) out.push_back(e);
  return out;
}

uint64_t EventHub::LastId() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_id_;
}

void EventHub::Close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}

bool EventHub::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

}  // namespace seamap::server
