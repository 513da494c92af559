#include "cli/shutdown_signal.h"

#include <pthread.h>
#include <signal.h>

#include <mutex>

namespace seamap::cli {
namespace {
std::mutex g_mutex;
}

ShutdownSignal::ShutdownSignal() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGUSR1);  // Release()
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  signal(SIGPIPE, SIG_IGN);  // a browser closing a connection must not end the process
}

ShutdownSignal::~ShutdownSignal() {
  Release();
  if (thread_.joinable()) thread_.join();
}

void ShutdownSignal::OnSignal(std::function<void()> on_signal) {
  on_signal_ = std::move(on_signal);
  thread_ = std::thread([this] {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGUSR1);
    int sig = 0;
    sigwait(&set, &sig);
    if (sig != SIGUSR1 && on_signal_) {
      std::lock_guard<std::mutex> lock(g_mutex);
      on_signal_();
    }
  });
}

void ShutdownSignal::Release() {
  if (thread_.joinable()) pthread_kill(thread_.native_handle(), SIGUSR1);
}

}  // namespace seamap::cli
