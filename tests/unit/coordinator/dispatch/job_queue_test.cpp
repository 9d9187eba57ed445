// Tests coordinator/dispatch/job_queue.cpp: the queue's order (put back at the front), leases that follow the
// median job time, and what an idle worker may take beyond the queue — a trial, a job held only by workers not
// proven, a backup — and leases taken back.
#include "coordinator/dispatch/job_queue.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

const JobTimings kTimings{/*liveness_ms=*/5000, /*backup_factor=*/4, /*backup_min_ms=*/1000, /*max_leases=*/3};
const JobQueue::Pick kAny = [](const OpenJob&) { return true; };

std::vector<uint64_t> add_jobs(JobQueue& queue, size_t count) {
  std::vector<uint64_t> ids;
  for (size_t t = 0; t < count; ++t) ids.push_back(queue.add(t, t + 1, 0).id);
  queue.enqueue(ids, /*front=*/false);
  return ids;
}

TEST(JobQueue, JobsGoOutInOrderAndOnesPutBackOrCutAgainGoFirst) {
  JobQueue queue(kTimings);
  const std::vector<uint64_t> ids = add_jobs(queue, 3);
  OpenJob* first = queue.take_queued(kAny);
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->id, ids[0]);
  EXPECT_FALSE(first->queued);
  queue.enqueue_front(*first);
  queue.enqueue_front(*first);  // once
  EXPECT_EQ(queue.queued(), (std::deque<uint64_t>{ids[0], ids[1], ids[2]}));

  const uint64_t a = queue.add(10, 11, 1).id, b = queue.add(11, 12, 1).id;
  queue.enqueue({a, b}, /*front=*/true);
  EXPECT_EQ(queue.queued(), (std::deque<uint64_t>{a, b, ids[0], ids[1], ids[2]}));
  // the first the picker allows
  EXPECT_EQ(queue.take_queued([&](const OpenJob& job) { return job.begin == 1; })->id, ids[1]);
  queue.erase(ids[2]);
  EXPECT_FALSE(queue.contains(ids[2]));
  EXPECT_EQ(queue.queued(), (std::deque<uint64_t>{a, b, ids[0]}));

  queue.clear();  // ids go on across batches: a late result of an earlier batch names no open job
  EXPECT_GT(queue.add(0, 1, 0).id, b);
}

TEST(JobQueue, TheLeaseIsLivenessUntilAJobFinishesThenFourTimesTheMedianAtLeastItsFloor) {
  JobQueue queue(kTimings);
  EXPECT_EQ(queue.lease_ms(), 5000);
  queue.finished_in(100);
  EXPECT_EQ(queue.lease_ms(), 1000);
  queue.finished_in(600);
  queue.finished_in(700);
  EXPECT_EQ(queue.lease_ms(), 2400);
  queue.clear();
  EXPECT_EQ(queue.lease_ms(), 5000);
}

TEST(JobQueue, AnIdleWorkerGetsATrialAJobOnlyUnprovenWorkersHoldOrABackupOfTheLongestHeld) {
  JobQueue queue(kTimings);
  add_jobs(queue, 3);
  OpenJob* j0 = queue.take_queued(kAny);
  OpenJob* j1 = queue.take_queued(kAny);
  OpenJob* j2 = queue.take_queued(kAny);
  queue.lease(*j0, "new", 0);
  queue.lease(*j0, "p1", 0);
  queue.lease(*j1, "p2", 100);
  queue.lease(*j2, "p3", 300);
  EXPECT_EQ(queue.take_queued(kAny), nullptr);

  EXPECT_EQ(queue.fewest_holders(kAny), j1);  // one holder, the first such
  const auto unproven = [](const WorkerId& id) { return id == "new"; };
  EXPECT_EQ(queue.held_only_by(unproven, kAny), nullptr);  // j0 also has a proven holder
  queue.open().at(j0->id).leases.pop_back();
  EXPECT_EQ(queue.held_only_by(unproven, kAny), j0);

  EXPECT_FALSE(queue.any_overdue(4999));  // no job finished: the lease is liveness
  EXPECT_EQ(queue.backup(4999, kAny), nullptr);
  EXPECT_TRUE(queue.any_overdue(5100));
  EXPECT_EQ(queue.backup(5200, kAny), j0);  // held longest
  EXPECT_EQ(queue.backup(5200, [&](const OpenJob& job) { return job.id != j0->id; }), j1);
  EXPECT_EQ(queue.backups(), 2);
}

TEST(JobQueue, ExpiredLeasesOfWorkersNotProvenAreTakenBackAndTheJobTaintedAndPutBack) {
  JobQueue queue(kTimings);
  add_jobs(queue, 2);
  OpenJob* j0 = queue.take_queued(kAny);
  OpenJob* j1 = queue.take_queued(kAny);
  queue.lease(*j0, "new", 0);
  queue.lease(*j1, "new", 0);
  queue.lease(*j1, "proven", 0);
  const auto not_proven = [](const WorkerId& id) { return id == "new"; };
  EXPECT_TRUE(queue.take_back_expired(4999, not_proven).empty());
  const auto taken = queue.take_back_expired(5000, not_proven);
  EXPECT_EQ(taken, (std::vector<std::pair<uint64_t, WorkerId>>{{j0->id, "new"}, {j1->id, "new"}}));
  EXPECT_EQ(queue.leases_expired(), 2);
  EXPECT_TRUE(j0->queued && j0->taken_back.contains("new"));  // what the lease run out means is trust's to say
  EXPECT_FALSE(j1->queued);  // its proven holder keeps it
  EXPECT_EQ(j1->leases.size(), 1u);
  EXPECT_EQ(queue.queued(), (std::deque<uint64_t>{j0->id}));
}

}  // namespace
}  // namespace poet
