// Tests coordinator/dispatch/batch_cut.cpp: about four jobs a thread, one job a worker when the batch goes out
// whole at once anyway, and the bounds.
#include "coordinator/dispatch/batch_cut.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

TEST(BatchCut, AboutFourJobsAThreadOrOneAWorkerWhenTheBatchGoesOutWholeAtOnce) {
  // 10,240 tasks on 256 one-thread workers: 1,024 jobs of 10, more than two a worker, so the queue balances them
  EXPECT_EQ(tasks_per_job(10'240, std::vector<int>(256, 1), 2, 64), 10u);
  // 512 tasks on 256 workers: two a worker would go out at once; one job each ends no later
  EXPECT_EQ(tasks_per_job(512, std::vector<int>(256, 1), 2, 64), 2u);
  // 40 tasks on two workers of two threads: jobs of 3 (about four a thread), more than two a worker
  EXPECT_EQ(tasks_per_job(40, {2, 2}, 2, 64), 3u);
  // nobody ready: one task a job, so that whoever comes takes a share
  EXPECT_EQ(tasks_per_job(4, {}, 2, 64), 1u);
  EXPECT_EQ(tasks_per_job(100'000, {1}, 2, 64), 64u);  // at most max_chunk
}

}  // namespace
}  // namespace poet
