#include "cli/shutdown_signal.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <cstdio>

namespace seamap::cli {
namespace {

sigset_t HandledSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGUSR1);  // Stop()
  return set;
}

}  // namespace

ShutdownSignal::ShutdownSignal() {
  sigset_t set = HandledSignals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  signal(SIGPIPE, SIG_IGN);  // a browser closing a connection must not end the process
}

ShutdownSignal::~ShutdownSignal() {
  Stop();
}

void ShutdownSignal::OnSignal(std::function<void()> on_signal) {
  on_signal_ = std::move(on_signal);
  thread_ = std::thread([this] {
    sigset_t set = HandledSignals();
    bool handled = false;
    while (true) {
      int sig = 0;
      sigwait(&set, &sig);
      if (sig == SIGUSR1) {
        if (stopping_) return;
        continue;  // someone else's SIGUSR1: not ours to act on
      }
      if (handled) {  // a second Ctrl-C: the user does not want to wait
        std::fprintf(stderr, "\nseamap: stopping now\n");
        _exit(130);
      }
      handled = true;
      if (on_signal_) on_signal_();
    }
  });
}

void ShutdownSignal::Stop() {
  if (!thread_.joinable()) return;
  stopping_ = true;
  pthread_kill(thread_.native_handle(), SIGUSR1);
  thread_.join();
}

}  // namespace seamap::cli
