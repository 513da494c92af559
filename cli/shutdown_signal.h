#pragma once
// Ctrl-C / SIGTERM for long-running commands (serve, replay): the signals are
// blocked in every thread and received by one waiting thread, which runs a
// callback, so stopping is an ordinary function call, not signal-handler code.
#include <functional>
#include <thread>

namespace seamap::cli {

class ShutdownSignal {
 public:
  // Call before starting any other thread.
  ShutdownSignal();
  ~ShutdownSignal();
  // Runs `on_signal` (once) in the signal thread when SIGINT or SIGTERM arrives.
  void OnSignal(std::function<void()> on_signal);
  // Wakes the signal thread without a signal (normal exit).
  void Release();

 private:
  std::thread thread_;
  std::function<void()> on_signal_;
};

}  // namespace seamap::cli
