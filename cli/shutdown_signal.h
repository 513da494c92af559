#pragma once
// Ctrl-C / SIGTERM for long-running commands (serve, replay): the signals are
// blocked in every thread and received by one waiting thread, which runs a
// callback, so stopping is an ordinary function call, not signal-handler code.
// A second Ctrl-C while the first is being handled ends the process at once.
#include <atomic>
#include <functional>
#include <thread>

namespace seamap::cli {

class ShutdownSignal {
 public:
  // Call before starting any other thread.
  ShutdownSignal();
  ~ShutdownSignal();  // Stop()
  // Runs `on_signal` (once) in the signal thread when SIGINT or SIGTERM arrives.
  void OnSignal(std::function<void()> on_signal);
  // Ends the signal thread (normal exit); call before what the callback uses goes away.
  void Stop();

 private:
  std::thread thread_;
  std::function<void()> on_signal_;
  std::atomic<bool> stopping_{false};
};

// Calls Stop() when the scope ends: declare it after the objects the callback uses.
struct StopSignalsOnExit {
  ShutdownSignal& signal;
  ~StopSignalsOnExit() { signal.Stop(); }
};

}  // namespace seamap::cli
