#pragma once
// Runs fn(i) for i in [0, n) on up to `threads` threads. Each index runs exactly once; callers write results
// into slot i, so the outcome never depends on the thread count or on scheduling. An exception thrown by fn is
// rethrown here after all threads have stopped.

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace poet {

template <class Fn>
void parallel_for(int n, int threads, Fn&& fn) {
  std::atomic<int> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    for (int i = next++; i < n; i = next++) {
      try {
        fn(i);
      } catch (...) {
        std::lock_guard lock(error_mutex);
        if (!error) error = std::current_exception();
        next = n;  // stop handing out work
      }
    }
  };
  const int extra = std::clamp(threads, 1, std::max(n, 1)) - 1;
  std::vector<std::thread> pool;
  pool.reserve(static_cast<size_t>(extra));
  for (int t = 0; t < extra; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace poet
