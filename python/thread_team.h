#pragma once
// A team of threads kept between calls: run(n, fn) calls fn(i) for each i in [0, n) once, on the calling thread
// and the team's, and returns when all are done (parallel_for's contract: callers write slot i, so the outcome
// never depends on the thread count; the first exception is rethrown after every thread has stopped). The vector
// env calls it every step, where starting threads afresh costs a fifth of a step with few walkers a thread.
// Hand-written rather than OpenMP's team: libgomp hangs in a child forked after it was used (Python's
// multiprocessing forks by default on Linux); a team that finds itself in a forked child starts a new one.
// One caller at a time.

#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace poet {

class ThreadTeam {
 public:
  explicit ThreadTeam(int threads);
  ~ThreadTeam();
  ThreadTeam(const ThreadTeam&) = delete;
  ThreadTeam& operator=(const ThreadTeam&) = delete;

  void run(int n, const std::function<void(int)>& fn);

 private:
  // What the threads share; a new one for each team, so that a forked child never touches its parent's.
  struct Shared {
    std::atomic<uint32_t> generation{0};  // bumped for each run (and to quit): the helpers wait on it
    std::atomic<int> pending{0};          // helpers still working on the current run
    // Each member's share [begin, end) of the indices, handed out through its cursor: a member works through its own
    // share, then takes from the others'. The same walkers stay on the same thread from step to step (their worlds
    // in its cache), and none waits while work is left.
    struct Share {
      alignas(64) std::atomic<int> next{0};
      int end = 0;
    };
    std::vector<Share> shares;
    const std::function<void(int)>* fn = nullptr;
    bool quit = false;
    std::mutex error_mutex;
    std::exception_ptr error;
  };

  void start();
  void abandon();
  static void work(Shared& shared, int member);
  static void help(Shared& shared, int member);

  int threads_ = 1;
  pid_t pid_ = 0;  // the process that started the helpers
  std::unique_ptr<Shared> shared_;
  std::vector<std::thread> helpers_;
};

}  // namespace poet
