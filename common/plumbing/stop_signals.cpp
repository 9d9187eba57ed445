#include "common/plumbing/stop_signals.h"

#include <pthread.h>
#include <unistd.h>

#include <thread>

namespace poet {

StopSignals::StopSignals(int fixed_exit_code, bool boundary_signal) : fixed_exit_code_(fixed_exit_code) {
  sigemptyset(&set_);
  sigaddset(&set_, SIGINT);
  sigaddset(&set_, SIGTERM);
  if (boundary_signal) sigaddset(&set_, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &set_, nullptr);
  std::thread([this] { watch(); }).detach();  // lives as long as the process
}

void StopSignals::loop_started(std::function<void()> on_stop) {
  on_stop_ = std::move(on_stop);
  in_loop_.store(true, std::memory_order_release);
}

void StopSignals::watch() {
  for (;;) {
    int signal = 0;
    if (sigwait(&set_, &signal) != 0) continue;
    if (signal == SIGUSR1) {  // whenever it comes, start-up included: the loop stops at its first boundary
      boundary_requested_.store(true, std::memory_order_release);
      continue;
    }
    if (!in_loop_.load(std::memory_order_acquire) || source_.stop_requested()) ::_exit(exit_code_for(signal));
    first_signal_.store(signal, std::memory_order_release);
    source_.request_stop();
    if (on_stop_) on_stop_();
  }
}

}  // namespace poet
