#pragma once
// SIGINT and SIGTERM for a process with threads (the coordinator, a worker): blocked in every thread and taken by
// one watcher thread with sigwait, so the reaction runs as ordinary code (a stop request is not
// async-signal-safe) and no rollout thread is ever interrupted. Until loop_started() a signal ends the process at
// once; after it the first signal requests a stop, and a second ends the process at once. The exit code is the
// shell's for a process ended by a signal, 128 + its number (SIGINT 130, SIGTERM 143: what docker stop and
// Kubernetes expect), or a fixed one.
// A process that can stop at a boundary of its own (the coordinator: between iterations) also takes SIGUSR1, at any
// time, as a request to do so (what SLURM's --signal=B:USR1@T sends before a time limit): it is recorded, never
// ends the process, and a later SIGINT or SIGTERM keeps its meaning.
// Construct it first thing in main, before any other thread exists, so that every thread inherits the mask.

#include <signal.h>

#include <atomic>
#include <functional>
#include <stop_token>

namespace poet {

class StopSignals {
 public:
  // fixed_exit_code < 0: exit with 128 + the signal's number. boundary_signal: take SIGUSR1 as a boundary stop.
  explicit StopSignals(int fixed_exit_code = -1, bool boundary_signal = false);
  // From now on the first signal requests a stop on token() and then calls on_stop (on the watcher thread).
  void loop_started(std::function<void()> on_stop = {});
  std::stop_token token() const { return source_.get_token(); }
  bool stop_requested() const { return source_.stop_requested(); }
  // The code to exit with after a requested stop: that of the signal that requested it.
  int exit_code() const { return exit_code_for(first_signal_.load(std::memory_order_acquire)); }
  // Whether SIGUSR1 asked for a stop at the next boundary (with boundary_signal).
  bool boundary_stop_requested() const { return boundary_requested_.load(std::memory_order_acquire); }

 private:
  [[noreturn]] void watch();
  int exit_code_for(int signal) const { return fixed_exit_code_ >= 0 ? fixed_exit_code_ : 128 + signal; }

  int fixed_exit_code_;
  std::atomic<int> first_signal_{0};
  sigset_t set_{};
  std::function<void()> on_stop_;  // written before in_loop_ is set, read after it is seen
  std::atomic<bool> in_loop_{false};
  std::atomic<bool> boundary_requested_{false};
  std::stop_source source_;
};

}  // namespace poet
