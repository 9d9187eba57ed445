#pragma once
// SIGINT and SIGTERM for a process with threads (the coordinator, a worker): blocked in every thread and taken by
// one watcher thread with sigwait, so the reaction runs as ordinary code (a stop request is not
// async-signal-safe) and no rollout thread is ever interrupted. Until loop_started() a signal ends the process at
// once with the given exit code; after it the first signal requests a stop, and a second ends the process at once.
// Construct it first thing in main, before any other thread exists, so that every thread inherits the mask.

#include <signal.h>

#include <atomic>
#include <functional>
#include <stop_token>

namespace poet {

class StopSignals {
 public:
  explicit StopSignals(int exit_code);
  // From now on the first signal requests a stop on token() and then calls on_stop (on the watcher thread).
  void loop_started(std::function<void()> on_stop = {});
  std::stop_token token() const { return source_.get_token(); }
  bool stop_requested() const { return source_.stop_requested(); }

 private:
  [[noreturn]] void watch();

  int exit_code_;
  sigset_t set_{};
  std::function<void()> on_stop_;  // written before in_loop_ is set, read after it is seen
  std::atomic<bool> in_loop_{false};
  std::stop_source source_;
};

}  // namespace poet
