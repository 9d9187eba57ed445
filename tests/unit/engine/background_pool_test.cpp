// BackgroundPool: every job submitted runs before wait() returns; a pool destroyed with jobs queued drops them
// and joins its threads, leaving nothing running.

#include "engine/background_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

namespace poet {
namespace {

TEST(BackgroundPool, WaitReturnsWhenEveryJobHasRun) {
  BackgroundPool pool(3);
  std::vector<int> done(200, 0);
  for (size_t i = 0; i < done.size(); ++i) pool.submit([&done, i] { done[i] += 1; });
  pool.wait();
  for (size_t i = 0; i < done.size(); ++i) EXPECT_EQ(done[i], 1) << i;
  pool.submit([&done] { done[0] += 1; });  // usable again after a wait
  pool.wait();
  EXPECT_EQ(done[0], 2);
}

TEST(BackgroundPool, WaitWithNothingSubmittedReturnsAtOnce) {
  BackgroundPool pool(2);
  pool.wait();
}

TEST(BackgroundPool, DestructionDropsQueuedJobsAndJoinsRunningOnes) {
  std::atomic<int> started{0}, finished{0};
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  std::jthread opener;
  {
    BackgroundPool pool(1);
    pool.submit([&] {
      started += 1;
      gate.wait();
      finished += 1;
    });
    for (int i = 0; i < 10; ++i) pool.submit([&] { started += 1; });
    while (started == 0) std::this_thread::yield();
    opener = std::jthread([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      release.set_value();
    });
  }  // joins the running job, drops the queued ones
  EXPECT_EQ(finished, 1);
  EXPECT_EQ(started, 1);
}

}  // namespace
}  // namespace poet
