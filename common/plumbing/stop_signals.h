#pragma once
// SIGINT and SIGTERM for a process with threads (the coordinator, a worker): blocked in every thread and taken by
// one watcher thread with sigwait, so the reaction runs as ordinary code (a stop request is not
// async-signal-safe) and no rollout thread is ever interrupted. Until loop_started() a signal ends the process at
// once; after it the first signal requests a stop, and a second ends the process at once. The exit code is the
// shell's for a process ended by a signal, 128 + its number (SIGINT 130, SIGTERM 143: what docker stop and
// Kubernetes expect), or a fixed one.
// Construct it first thing in main, before any other thread exists, so that every thread inherits the mask.

#include <signal.h>

#include <atomic>
#include <functional>
#include <stop_token>

namespace poet {

class StopSignals {
 public:
  // fixed_exit_code < 0: exit with 128 + the signal's number.
  explicit StopSignals(int fixed_exit_code = -1);
  // From now on the first signal requests a stop on token() and then calls on_stop (on the watcher thread).
  void loop_started(std::function<void()> on_stop = {});
  std::stop_token token() const { return source_.get_token(); }
  bool stop_requested() const { return source_.stop_requested(); }
  // The code to exit with after a requested stop: that of the signal that requested it.
  int exit_code() const { return exit_code_for(first_signal_.load(std::memory_order_acquire)); }

 private:
  [[noreturn]] void watch();
  int exit_code_for(int signal) const { return fixed_exit_code_ >= 0 ? fixed_exit_code_ : 128 + signal; }

  int fixed_exit_code_;
  std::atomic<int> first_signal_{0};
  sigset_t set_{};
  std::function<void()> on_stop_;  // written before in_loop_ is set, read after it is seen
  std::atomic<bool> in_loop_{false};
  std::stop_source source_;
};

}  // namespace poet
