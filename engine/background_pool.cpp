#include "engine/background_pool.h"

namespace poet {

BackgroundPool::~BackgroundPool() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
    queue_.clear();
  }
  queued_.notify_all();
  for (std::thread& t : pool_) t.join();
}

void BackgroundPool::submit(std::function<void()> job) {
  {
    std::lock_guard lock(mutex_);
    if (pool_.empty())
      for (int t = 0; t < threads_; ++t) pool_.emplace_back([this] { work(); });
    queue_.push_back(std::move(job));
  }
  queued_.notify_one();
}

void BackgroundPool::wait() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] { return queue_.empty() && running_ == 0; });
}

void BackgroundPool::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    queued_.wait(lock, [&] { return closing_ || !queue_.empty(); });
    if (closing_) return;
    std::function<void()> job = std::move(queue_.front());
    queue_.pop_front();
    running_ += 1;
    lock.unlock();
    job();
    lock.lock();
    running_ -= 1;
    if (queue_.empty() && running_ == 0) idle_.notify_all();
  }
}

}  // namespace poet
