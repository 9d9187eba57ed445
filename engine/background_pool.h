#pragma once
// A few threads that run jobs while their owner waits on something else (a batch's rollouts). Jobs run in
// submission order across up to `threads` threads, started on the first submission. Jobs must not throw.
// Thread-safe; the destructor drops the jobs not yet started and joins the threads, so no job outlives the pool.

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace poet {

class BackgroundPool {
 public:
  explicit BackgroundPool(int threads) : threads_(threads < 1 ? 1 : threads) {}
  ~BackgroundPool();
  BackgroundPool(const BackgroundPool&) = delete;
  BackgroundPool& operator=(const BackgroundPool&) = delete;

  void submit(std::function<void()> job);
  // Returns when every job submitted so far has run.
  void wait();

 private:
  void work();

  int threads_;
  std::mutex mutex_;
  std::condition_variable queued_;  // workers wait for jobs
  std::condition_variable idle_;    // wait() waits for the last job
  std::deque<std::function<void()>> queue_;
  int running_ = 0;  // jobs taken from the queue and not finished
  bool closing_ = false;
  std::vector<std::thread> pool_;
};

}  // namespace poet
