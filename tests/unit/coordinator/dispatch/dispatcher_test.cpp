// Tests coordinator/dispatch/dispatcher.cpp with a fake clock and no sockets: hellos and refusals, a batch cut
// into jobs spread over workers, θ sent once per worker and batch, results in task order, duplicates and
// strangers dropped, re-queueing on departure and on silence, the poison-job rule naming the task, and backup jobs
// for a worker that holds its jobs far longer than the batch's jobs take.

#include "coordinator/dispatch/dispatcher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <set>
#include <span>
#include <tuple>

#include "common/formats/rollout_task_proto.h"
#include "dispatch_fixture.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {
namespace {

using namespace dispatch_fixture;

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

// The batch's results in task order: each task's reward is its index (answer()).
void expect_task_order(const std::vector<RolloutResult>& results) {
  for (size_t i = 0; i < results.size(); ++i) EXPECT_EQ(results[i].total_reward, static_cast<double>(i)) << i;
}

TEST(Dispatcher, RefusesOtherVersionsAndBuilds) {
  Dispatcher d(settings());
  wire::Hello old = hello();
  old.set_protocol_version(99);
  EXPECT_TRUE(d.on_hello("a", old, 0).has_refused());
  const wire::CoordinatorMessage other = d.on_hello("b", hello(1, 7), 0);
  ASSERT_TRUE(other.has_refused());
  EXPECT_TRUE(contains(other.refused().reason(), "fingerprint")) << other.refused().reason();
  EXPECT_EQ(d.worker_count(), 0u);
  EXPECT_EQ(d.view(0).dropped_frames.at("wrong_version"), 1);
  EXPECT_EQ(d.view(0).dropped_frames.at("wrong_fingerprint"), 1);
  const wire::CoordinatorMessage ok = d.on_hello("c", hello(), 0);
  ASSERT_TRUE(ok.has_welcome());
  EXPECT_EQ(ok.welcome().liveness_ms(), 500u);
  EXPECT_EQ(d.worker_count(), 1u);
}

TEST(Dispatcher, ABatchSpreadsOverWorkersAndComesBackInTaskOrder) {
  Dispatcher d(settings());
  join(d, "a", hello(2), 0);
  join(d, "b", hello(2), 0);
  d.start_batch(batch(40));
  std::vector<Outgoing> jobs = jobs_in(d.outgoing(1));
  ASSERT_EQ(jobs.size(), 4u);  // two ahead for each worker: with jobs enough for all, consecutive ones
  EXPECT_EQ(jobs[0].worker, "a");
  EXPECT_EQ(jobs[1].worker, "a");
  EXPECT_EQ(jobs[2].worker, "b");
  EXPECT_EQ(jobs[1].message.job().job_id(), jobs[0].message.job().job_id() + 1);
  // θ goes once to each worker in the batch, then by hash only; the frame parses as the whole Job
  const auto on_wire = [](const Outgoing& out) {
    wire::CoordinatorMessage parsed;
    EXPECT_TRUE(parsed.ParseFromString(out.frame()));
    EXPECT_EQ(parsed.job().tasks_size(), out.message.job().tasks_size());
    EXPECT_EQ(parsed.job().job_id(), out.message.job().job_id());
    return parsed.job();
  };
  EXPECT_EQ(on_wire(jobs[0]).thetas_size(), 1);
  EXPECT_EQ(on_wire(jobs[1]).thetas_size(), 0);
  EXPECT_EQ(on_wire(jobs[2]).thetas_size(), 1);
  EXPECT_EQ(on_wire(jobs[0]).thetas(0).hash(), theta_hash(*batch(1)[0].theta));
  EXPECT_EQ(on_wire(jobs[0]).thetas(0).values_size(), batch(1)[0].theta->size());
  EXPECT_EQ(on_wire(jobs[0]).thetas(0).values(7), (*batch(1)[0].theta)[7]);
  EXPECT_EQ(on_wire(jobs[1]).SerializeAsString(), jobs[1].message.job().SerializeAsString());
  Millis now = 2;
  while (!d.batch_done()) {
    ASSERT_FALSE(jobs.empty()) << "nothing in flight and the batch is not done";
    // answer in reverse order: results still land in task order
    for (auto it = jobs.rbegin(); it != jobs.rend(); ++it) d.on_result(it->worker, answer(it->message.job()), now);
    jobs = jobs_in(d.outgoing(++now));
  }
  const std::vector<RolloutResult> results = d.take_results();
  ASSERT_EQ(results.size(), 40u);
  expect_task_order(results);
}

TEST(Dispatcher, ABatchThatGoesOutWholeAtOnceIsCutIntoOneJobAWorker) {
  // four workers, two jobs ahead each: a batch of up to eight one-task jobs would go out whole at once, with no
  // queue left to balance, so it goes as one job a worker; a larger batch keeps its small jobs
  for (const auto& [tasks, expected_jobs, expected_per_job] :
       {std::tuple{4, 4, 1}, std::tuple{7, 4, 2}, std::tuple{8, 4, 2}, std::tuple{9, 9, 1}, std::tuple{40, 14, 3}}) {
    Dispatcher d(settings());
    for (const char* id : {"a", "b", "c", "d"}) join(d, id, hello(), 0);
    d.start_batch(batch(static_cast<size_t>(tasks)));
    std::vector<Outgoing> sent = jobs_in(d.outgoing(1));
    EXPECT_EQ(sent.size() + static_cast<size_t>(d.view(0).queue_depth), static_cast<size_t>(expected_jobs)) << tasks;
    EXPECT_EQ(sent.front().message.job().tasks_size(), expected_per_job) << tasks;
    std::set<WorkerId> workers;
    for (const Outgoing& o : sent) workers.insert(o.worker);
    EXPECT_EQ(workers.size(), std::min<size_t>(4, sent.size())) << tasks;
  }
}

TEST(Dispatcher, ItsViewHoldsItsWorkersWhenLastHeardAndEveryCounter) {
  Dispatcher d(settings());
  join(d, "a", hello(3), 0);
  join(d, "b", hello(), 0);
  d.heard_from("a", 1'200);
  d.start_batch(batch(8));
  const std::vector<Outgoing> sent = jobs_in(d.outgoing(1'300));
  d.on_result("stranger", answer(sent[0].message.job()), 1'400);
  const DispatchView view = d.view(2'500);
  EXPECT_EQ(view.at, 2'500);
  ASSERT_EQ(view.workers.size(), 2u);
  EXPECT_EQ(view.workers[0].id, "a");
  EXPECT_EQ(view.workers[0].threads, 3);
  EXPECT_EQ(view.workers[0].last_heard, 1'200);  // a heartbeat 1.3 s before the view
  EXPECT_EQ(view.ready_workers, 2u);
  EXPECT_EQ(view.in_flight_jobs, static_cast<int64_t>(sent.size()));  // every job sent is held
  EXPECT_EQ(view.queue_depth, 8 - static_cast<int64_t>(sent.size()));  // one task a job
  EXPECT_EQ(view.workers_joined, 2);
  EXPECT_EQ(view.dropped_frames.at("unexpected_result"), 1);
}

TEST(Dispatcher, DuplicatesAndStrangersAreDropped) {
  Dispatcher d(one_task_jobs());
  join(d, "a", hello(), 0);
  d.start_batch(batch(2));
  const std::vector<Outgoing> jobs = jobs_in(d.outgoing(1));
  ASSERT_FALSE(jobs.empty());
  const wire::Result result = answer(jobs[0].message.job());
  d.on_result("stranger", result, 2);
  EXPECT_EQ(d.view(0).dropped_frames.at("unexpected_result"), 1);
  d.on_result("a", result, 2);
  d.on_result("a", result, 3);  // again
  EXPECT_EQ(d.view(0).dropped_frames.at("unexpected_result"), 2);
  ASSERT_EQ(jobs.size(), 2u);  // one task a job, both sent at once
  wire::Result short_result = answer(jobs[1].message.job());
  short_result.mutable_results()->RemoveLast();
  d.on_result("a", short_result, 5);
  EXPECT_EQ(d.view(0).dropped_frames.at("bad_result"), 1);
  EXPECT_FALSE(d.heard_from("stranger", 5));
}

TEST(Dispatcher, JobsOfASilentWorkerGoToTheOthers) {
  Dispatcher d(settings());
  join(d, "a", hello(), 0);
  join(d, "b", hello(), 0);
  d.start_batch(batch(8));
  std::vector<Outgoing> jobs = jobs_in(d.outgoing(1));
  // b answers and keeps beating; a goes silent
  Millis now = 1;
  while (!d.batch_done() && now < 5000) {
    now += 50;
    for (const Outgoing& o : jobs)
      if (o.worker == "b") d.on_result("b", answer(o.message.job()), now);
    d.heard_from("b", now);
    const std::vector<WorkerId> dead = d.expire(now);
    if (!dead.empty()) {
      EXPECT_EQ(dead, std::vector<WorkerId>{"a"});
    }
    jobs = jobs_in(d.outgoing(now));
  }
  ASSERT_TRUE(d.batch_done());
  EXPECT_EQ(d.worker_count(), 1u);
  const std::vector<RolloutResult> results = d.take_results();
  expect_task_order(results);
}

TEST(Dispatcher, AJobThatKillsEveryWorkerStopsTheRunNamingTheTask) {
  Dispatcher d(settings());
  d.start_batch(batch(3));
  // task 1 kills whoever runs it; the others are answered
  for (int round = 0; round < 10 && !d.failure(); ++round) {
    const WorkerId id = "w" + std::to_string(round);
    join(d, id, hello(), round * 1000);
    for (const Outgoing& o : jobs_in(d.outgoing(round * 1000))) {
      const wire::Job& job = o.message.job();
      bool deadly = false;
      for (const wire::Task& t : job.tasks()) deadly = deadly || t.env().seed() == 1;
      if (deadly) {
        d.remove_worker(id, /*died=*/true);
        break;
      }
      d.on_result(id, answer(job), round * 1000);
    }
  }
  ASSERT_TRUE(d.failure());
  EXPECT_TRUE(contains(*d.failure(), "task 1 of the batch")) << *d.failure();
  EXPECT_TRUE(contains(*d.failure(), "3 workers")) << *d.failure();
}

TEST(Dispatcher, HeartbeatsGoToIdleWorkers) {
  Dispatcher d(settings());
  join(d, "a", hello(), 0);
  EXPECT_TRUE(d.outgoing(50).empty());
  const std::vector<Outgoing> out = d.outgoing(100);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].message.has_heartbeat());
}

TEST(Dispatcher, AWorkerGetsJobsOnlyOnceItAnswersTheWelcome) {
  Dispatcher d(settings());
  ASSERT_TRUE(d.on_hello("mute", hello(), 0).has_welcome());
  d.start_batch(batch(4));
  EXPECT_TRUE(jobs_in(d.outgoing(1)).empty()) << "a peer that only said Hello holds no work";
  // it stays silent and expires: nothing was lost with it, so no task counts a death
  EXPECT_EQ(d.expire(600), std::vector<WorkerId>{"mute"});
  EXPECT_EQ(d.view(0).queue_depth, 4);  // one task a job (nobody ready when the batch was cut), none split
  join(d, "real", hello(), 600);
  for (Millis now = 601; !d.batch_done() && now < 700; ++now) {
    for (const Outgoing& o : jobs_in(d.outgoing(now))) d.on_result("real", answer(o.message.job()), now);
  }
  EXPECT_TRUE(d.batch_done());
  EXPECT_FALSE(d.failure());
}

TEST(Dispatcher, HellosBeyondTheWorkerLimitAreRefusedAndCounted) {
  DispatchSettings s = settings();
  s.max_workers = 3;
  Dispatcher d(s);
  for (int i = 0; i < 5; ++i) d.on_hello("w" + std::to_string(i), hello(), 0);
  EXPECT_EQ(d.worker_count(), 3u);
  EXPECT_EQ(d.view(0).dropped_frames.at("worker_limit"), 2);
  const wire::CoordinatorMessage again = d.on_hello("w0", hello(), 1);  // a known worker starting afresh
  EXPECT_TRUE(again.has_welcome());
  const wire::CoordinatorMessage refused = d.on_hello("w9", hello(), 1);
  ASSERT_TRUE(refused.has_refused());
  EXPECT_TRUE(contains(refused.refused().reason(), "limit")) << refused.refused().reason();
}

// Two workers, a batch of 4 one-task jobs (d made with one_task_jobs()): a holds jobs 1 and 3, b answers its 2 and 4 at
// time 20; a beats but never answers. Returns a's jobs.
std::vector<wire::Job> batch_with_a_silent_holder(Dispatcher& d) {
  join(d, "a", hello(), 0);
  join(d, "b", hello(), 0);
  d.start_batch(batch(4));
  std::vector<wire::Job> held_by_a;
  for (const Outgoing& o : jobs_in(d.outgoing(1))) {
    if (o.worker == "a") held_by_a.push_back(o.message.job());
    if (o.worker == "b") d.on_result("b", answer(o.message.job()), 20);
  }
  return held_by_a;
}

// a's jobs as sent to b once the backup time has passed, b and a beating until then.
std::vector<wire::Job> backups_at(Dispatcher& d, Millis until) {
  std::vector<wire::Job> to_b;
  for (Millis now = 50; now <= until; now += 50) {
    d.heard_from("a", now);
    d.heard_from("b", now);
    EXPECT_TRUE(d.expire(now).empty());
    for (const Outgoing& o : jobs_in(d.outgoing(now))) {
      EXPECT_EQ(o.worker, "b");
      to_b.push_back(o.message.job());
    }
  }
  return to_b;
}

TEST(Dispatcher, AJobHeldFarLongerThanTheBatchsJobsGoesToAnIdleWorkerToo) {
  Dispatcher d(one_task_jobs());  // backups after 4 × the median job time, at least 1000 ms
  const std::vector<wire::Job> held_by_a = batch_with_a_silent_holder(d);
  ASSERT_EQ(held_by_a.size(), 2u);
  EXPECT_TRUE(backups_at(d, 950).empty());  // b's jobs took 19 ms, but not before backup_min_ms
  const std::vector<wire::Job> to_b = backups_at(d, 1050);
  ASSERT_EQ(to_b.size(), 2u);
  EXPECT_EQ(d.backup_jobs(), 2);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(to_b[i].job_id(), held_by_a[i].job_id());  // the longest held first
    EXPECT_EQ(to_b[i].tasks(0).env().seed(), held_by_a[i].tasks(0).env().seed());
  }
  for (const wire::Job& job : to_b) d.on_result("b", answer(job), 1100);
  ASSERT_TRUE(d.batch_done());
  // a's answers come late: dropped and counted, the results unchanged
  for (const wire::Job& job : held_by_a) d.on_result("a", answer(job), 1200);
  EXPECT_EQ(d.view(0).dropped_frames.at("late_result"), 2);
  EXPECT_FALSE(d.view(0).dropped_frames.contains("unexpected_result"));
  const std::vector<RolloutResult> results = d.take_results();
  ASSERT_EQ(results.size(), 4u);
  expect_task_order(results);
}

TEST(Dispatcher, TheFirstHolderToAnswerABackedUpJobWins) {
  Dispatcher d(one_task_jobs());
  const std::vector<wire::Job> held_by_a = batch_with_a_silent_holder(d);
  const std::vector<wire::Job> to_b = backups_at(d, 1050);
  ASSERT_EQ(to_b.size(), 2u);
  d.on_result("a", answer(held_by_a[0]), 1060);  // a answers one after all
  d.on_result("b", answer(to_b[0]), 1070);
  d.on_result("b", answer(to_b[1]), 1080);
  d.on_result("a", answer(held_by_a[1]), 1090);
  ASSERT_TRUE(d.batch_done());
  EXPECT_EQ(d.view(0).dropped_frames.at("late_result"), 2);  // one from each
  EXPECT_EQ(d.view(0).in_flight_jobs, 0);
  const std::vector<RolloutResult> results = d.take_results();
  expect_task_order(results);
}

TEST(Dispatcher, AHolderLostWhileItsBackupRunsLeavesTheJobToTheBackup) {
  Dispatcher d(one_task_jobs());
  batch_with_a_silent_holder(d);
  const std::vector<wire::Job> to_b = backups_at(d, 1050);
  ASSERT_EQ(to_b.size(), 2u);
  d.remove_worker("a", /*died=*/true);
  EXPECT_EQ(d.view(0).queue_depth, 0);  // nothing re-queued: b holds both
  EXPECT_TRUE(jobs_in(d.outgoing(1100)).empty());
  for (const wire::Job& job : to_b) d.on_result("b", answer(job), 1150);
  ASSERT_TRUE(d.batch_done());
  EXPECT_FALSE(d.failure());
}

TEST(Dispatcher, NoBackupsWhenTurnedOffOrWhileJobsWait) {
  DispatchSettings off = settings();
  off.backup_factor = 0;
  Dispatcher d(off);
  batch_with_a_silent_holder(d);
  EXPECT_TRUE(backups_at(d, 3000).empty());
  EXPECT_EQ(d.backup_jobs(), 0);

  // jobs still queued go out before any backup: b's jobs take 1 ms, and when b next asks, long after a's jobs
  // are due a backup, it gets the queue's next jobs
  Dispatcher e(settings());
  join(e, "a", hello(), 0);
  join(e, "b", hello(), 0);
  e.start_batch(batch(8));  // one task a job: a holds 1 and 3, b 2 and 4, 5 to 8 wait
  std::set<uint64_t> held_by_a;
  for (const Outgoing& o : jobs_in(e.outgoing(1))) {
    if (o.worker == "a") held_by_a.insert(o.message.job().job_id());
    if (o.worker == "b") e.on_result("b", answer(o.message.job()), 2);
  }
  ASSERT_EQ(held_by_a.size(), 2u);
  e.heard_from("a", 4000);
  e.heard_from("b", 4000);
  const std::vector<Outgoing> next = jobs_in(e.outgoing(4000));
  ASSERT_EQ(next.size(), 2u);
  for (const Outgoing& o : next) {
    EXPECT_EQ(o.worker, "b");
    EXPECT_FALSE(held_by_a.contains(o.message.job().job_id()));
  }
  EXPECT_EQ(e.view(0).queue_depth, 2);
  EXPECT_EQ(e.backup_jobs(), 0);
}

// ---------------------------------------------------------------------------------------------------------
// Workers not started by this coordinator earn trust by returning results.

// Answers every job in `out` given to worker `id`, until the batch is done or nothing more goes out; jobs of the
// workers in `silent` are kept unanswered; the coordinator's checks are settled at once. The clock advances 10 ms
// a round.
void drive(Dispatcher& d, std::vector<Outgoing> out, Millis& now, const std::set<WorkerId>& silent = {}) {
  for (int round = 0; round < 10'000 && !d.batch_done() && !d.failure(); ++round) {
    for (const Outgoing& o : jobs_in(out))
      if (!silent.contains(o.worker)) d.on_result(o.worker, answer(o.message.job()), now);
    for (const Dispatcher::CoordinatorCheck& check : d.take_coordinator_checks())
      d.settle_by_coordinator(check.batch_id, check.job_id, coordinators_results(check));
    now += 10;
    for (const WorkerView& w : d.workers()) d.heard_from(w.id, now);  // every worker heartbeats
    out = d.outgoing(now);
  }
}

TEST(Dispatcher, PeersThatNeverAnswerDelayNothingOnceAWorkerIsProven) {
  Dispatcher d(settings());
  for (int i = 0; i < 50; ++i) join(d, "silent-" + std::to_string(i), stranger_hello("silent"), 0);
  join(d, "real", stranger_hello("real"), 0);
  d.start_batch(batch(200));
  std::vector<Outgoing> out = d.outgoing(1);
  for (const WorkerView& w : d.workers()) EXPECT_EQ(w.jobs_held, 1u) << w.id << ": one job until proven";
  std::set<WorkerId> silent;
  for (int i = 0; i < 50; ++i) silent.insert("silent-" + std::to_string(i));
  Millis now = 1;
  drive(d, out, now, silent);
  ASSERT_TRUE(d.batch_done());
  ASSERT_FALSE(d.failure());
  // the real worker, proven by its first answer, works through the queue two jobs at a time (a round of 10 ms each)
  // and then takes the silent peers' jobs at once: about 125 rounds, with no lease (1 s here) run out
  EXPECT_LT(now, 1 + 200 * 10) << "the batch took " << now << " ms";
  expect_task_order(d.take_results());

  // the next batch: silent peers take jobs again, and the proven worker backs them up as soon as the queue is empty
  d.start_batch(batch(20));
  const Millis started = now;
  drive(d, d.outgoing(now), now, silent);
  ASSERT_TRUE(d.batch_done());
  EXPECT_LT(now - started, settings().liveness_ms) << "no lease is waited for";
  expect_task_order(d.take_results());
}

// A new worker's trial (a copy of an open job) outlives its batch; it is sent nothing more until it answers, demoted
// once a lease has passed, and proven when its answer comes after all: a slow newcomer is not lost.
TEST(Dispatcher, ATrialAnsweredAfterItsBatchEndedProvesTheWorker) {
  Dispatcher d(settings());
  join(d, "p", hello(), 0);  // local: proven
  join(d, "n", stranger_hello("n"), 0);
  d.start_batch(batch(1));
  std::optional<Outgoing> trial;
  for (const Outgoing& o : jobs_in(d.outgoing(1))) {
    if (o.worker == "p") d.on_result("p", answer(o.message.job()), 2);
    if (o.worker == "n") trial = o;
  }
  ASSERT_TRUE(trial) << "the newcomer was sent a copy of the open job";
  ASSERT_TRUE(d.batch_done());
  d.take_results();
  d.start_batch(batch(4));
  for (Millis now = 10; now <= 2000; now += 10) {
    d.heard_from("p", now);
    d.heard_from("n", now);
    for (const Outgoing& o : jobs_in(d.outgoing(now))) {
      EXPECT_EQ(o.worker, "p") << "nothing more for a worker whose trial is unanswered";
      d.on_result("p", answer(o.message.job()), now);
    }
    if (d.batch_done()) d.take_results(), d.start_batch(batch(4));
  }
  auto view = [&](const WorkerId& id) {
    for (const WorkerView& w : d.workers())
      if (w.id == id) return w;
    return WorkerView{};
  };
  EXPECT_TRUE(view("n").demoted) << "its trial ran past the lease";
  d.on_result("n", answer(trial->message.job()), 2001);  // it comes after all
  EXPECT_TRUE(view("n").proven);
  EXPECT_FALSE(view("n").demoted);
  bool sent_to_n = false;
  for (const Outgoing& o : jobs_in(d.outgoing(2002))) sent_to_n = sent_to_n || o.worker == "n";
  EXPECT_TRUE(sent_to_n);
}

TEST(Dispatcher, ErrorsAndDeathsOfPeersNotProvenDoNotStopTheRun) {
  Dispatcher d(settings());
  join(d, "real", hello(), 0);  // local: proven
  for (int i = 0; i < 5; ++i) join(d, "peer-" + std::to_string(i), stranger_hello("peer"), 0);
  d.start_batch(batch(40));
  Millis now = 1;
  std::vector<Outgoing> out = d.outgoing(now);
  std::vector<Outgoing> for_real;
  for (const Outgoing& o : jobs_in(out)) {  // each peer takes a job and fails it: an error, or vanishing with it
    if (o.worker == "real") {
      for_real.push_back(o);
    } else if (o.worker.back() % 2 == 0) {
      wire::Result refusal;
      refusal.set_job_id(o.message.job().job_id());
      refusal.set_error("no");
      d.on_result(o.worker, refusal, now);
    } else {
      d.remove_worker(o.worker, /*died=*/true);
    }
  }
  EXPECT_FALSE(d.failure()) << *d.failure();
  EXPECT_EQ(d.view(0).dropped_frames.at("error_from_unproven"), 3);
  EXPECT_EQ(d.referee().counts().demoted, 3);
  drive(d, for_real, now);
  EXPECT_TRUE(d.batch_done());
  EXPECT_FALSE(d.failure());
  const std::vector<RolloutResult> results = d.take_results();
  expect_task_order(results);
}

TEST(Dispatcher, AnErrorStopsTheRunWhenTwoProvenWorkersAgree) {
  Dispatcher d(settings());
  join(d, "a", hello(), 0);
  join(d, "b", hello(), 0);
  d.start_batch(batch(1));
  Millis now = 1;
  for (int i = 0; i < 2; ++i) {
    const std::vector<Outgoing> jobs = jobs_in(d.outgoing(now++));
    ASSERT_EQ(jobs.size(), 1u);
    wire::Result refusal;
    refusal.set_job_id(jobs[0].message.job().job_id());
    refusal.set_error("task refused");
    d.on_result(jobs[0].worker, refusal, now);
    if (i == 0) {
      EXPECT_FALSE(d.failure()) << "one proven worker of two is not enough";
    }
  }
  ASSERT_TRUE(d.failure());
  EXPECT_TRUE(contains(*d.failure(), "task refused")) << *d.failure();
  EXPECT_TRUE(contains(*d.failure(), "and so did 1 other worker")) << *d.failure();
}

// answer(), except that the worker `liar` adds 1 to every reward.
wire::Result answer_lying_as(const Outgoing& job, const WorkerId& liar) {
  wire::Result r = answer(job.message.job());
  if (job.worker == liar)
    for (wire::TaskResult& t : *r.mutable_results()) t.set_total_reward(t.total_reward() + 1);
  return r;
}

// One round of a batch with a liar: every job answered (the liar's wrongly), the coordinator's own checks settled
// honestly, then 10 ms on, every worker heard from, and what goes out next.
std::vector<Outgoing> answer_round(Dispatcher& d, const std::vector<Outgoing>& out, Millis& now) {
  for (const Outgoing& o : jobs_in(out)) d.on_result(o.worker, answer_lying_as(o, "liar"), now);
  for (const Dispatcher::CoordinatorCheck& check : d.take_coordinator_checks())
    d.settle_by_coordinator(check.batch_id, check.job_id, coordinators_results(check));
  now += 10;
  for (const WorkerView& w : d.workers()) d.heard_from(w.id, now);
  return d.outgoing(now);
}

// Three newcomers on probation, one lying: none confirms another's answers (independent witnesses, rule 2), so the
// coordinator checks the first ones, and the honest two, once past probation, check the rest.
TEST(Dispatcher, AWrongWorkerIsFoundRefusedAndItsResultsRedone) {
  Dispatcher d(checking_every_job());
  for (const char* id : {"liar", "b", "c"}) join(d, id, stranger_hello(id), 0);
  d.start_batch(batch(30));
  Millis now = 1;
  std::vector<Outgoing> out = d.outgoing(now);
  bool refused_sent = false;
  for (int round = 0; round < 1000 && !d.batch_done() && !d.failure(); ++round) {
    for (const Outgoing& o : out) {
      if (o.message.has_refused()) refused_sent = refused_sent || o.worker == "liar";
      if (o.message.has_job()) d.on_result(o.worker, answer_lying_as(o, "liar"), now);
    }
    for (const Dispatcher::CoordinatorCheck& check : d.take_coordinator_checks())
      d.settle_by_coordinator(check.batch_id, check.job_id, coordinators_results(check));
    now += 10;
    for (const WorkerView& w : d.workers()) d.heard_from(w.id, now);
    out = d.outgoing(now);
  }
  ASSERT_FALSE(d.failure()) << *d.failure();
  ASSERT_TRUE(d.batch_done());
  EXPECT_TRUE(refused_sent);
  ASSERT_EQ(d.referee().refusals().size(), 1u);
  EXPECT_EQ(d.referee().refusals()[0].name, "liar");
  EXPECT_GT(d.view(0).verified_jobs, 0);
  EXPECT_TRUE(d.on_hello("liar", stranger_hello("liar"), now).has_refused()) << "refused from then on";
  // every range is reported final once, at the end, with the right numbers
  std::vector<int> reported(30, 0);
  for (const Dispatcher::Ready& ready : d.take_ready())
    for (size_t t = ready.first; t < ready.first + ready.results.size(); ++t) reported[t] += 1;
  for (size_t t = 0; t < 30; ++t) EXPECT_EQ(reported[t], 1) << t;
  expect_task_order(d.take_results());
}

// One liar and one honest worker, both on probation: neither may check the other's answers (rule 2), so each is
// handed to the coordinator, whose own answer (here the honest one: reward = the task's course seed) refuses the
// liar; the batch ends right.
TEST(Dispatcher, WithNoThirdWorkerTheCoordinatorSettlesAMismatchItself) {
  Dispatcher d(checking_every_job());
  for (const char* id : {"liar", "honest"}) join(d, id, stranger_hello(id), 0);
  d.start_batch(batch(12));
  Millis now = 1;
  std::vector<Outgoing> out = d.outgoing(now);
  int disputes = 0;
  for (int round = 0; round < 1000 && !d.batch_done() && !d.failure(); ++round) {
    for (const Outgoing& o : out)
      if (o.message.has_job()) d.on_result(o.worker, answer_lying_as(o, "liar"), now);
    now += 10;
    for (const WorkerView& w : d.workers()) d.heard_from(w.id, now);
    out = d.outgoing(now);
    const std::vector<Dispatcher::CoordinatorCheck> taken = d.take_coordinator_checks();
    for (const Outgoing& o : d.outgoing(now)) out.push_back(o);  // a pass that finds the checks unsettled still
    for (const Dispatcher::CoordinatorCheck& again : d.take_coordinator_checks())
      for (const Dispatcher::CoordinatorCheck& check : taken)
        EXPECT_NE(again.job_id, check.job_id) << "a check is handed out once";
    for (const Dispatcher::CoordinatorCheck& check : taken) {
      disputes += check.disputed ? 1 : 0;
      const std::vector<RolloutResult> own = coordinators_results(check);
      const int64_t settled = d.view(0).coordinator_checks;
      d.settle_by_coordinator(check.batch_id + 1, check.job_id, own);  // another batch's: ignored
      EXPECT_EQ(d.view(0).coordinator_checks, settled);
      d.settle_by_coordinator(check.batch_id, check.job_id, own);
      const int64_t after = d.view(0).coordinator_checks;
      d.settle_by_coordinator(check.batch_id, check.job_id, own);  // settled already: ignored
      EXPECT_EQ(d.view(0).coordinator_checks, after);
    }
  }
  ASSERT_FALSE(d.failure()) << *d.failure();
  ASSERT_TRUE(d.batch_done()) << "queue " << d.view(0).queue_depth;
  EXPECT_EQ(disputes, 0) << "no answer on probation is compared with another on probation";
  EXPECT_GE(d.view(0).coordinator_checks, 1);
  ASSERT_EQ(d.referee().refusals().size(), 1u);
  EXPECT_EQ(d.referee().refusals()[0].name, "liar");
  EXPECT_TRUE(d.on_hello("liar", stranger_hello("liar"), now).has_refused());
  expect_task_order(d.take_results());
}

// A proven worker that takes a check and sits on it: proven holders' leases do not expire and the worker whose
// answer waits cannot check itself, so once the lease has passed the coordinator checks the job.
TEST(Dispatcher, ACheckHeldPastItsLeaseGoesToTheCoordinator) {
  Dispatcher d(checking_every_job());
  join(d, "h", stranger_hello("h"), 0);
  join(d, "m", stranger_hello("m"), 0);
  d.start_batch(batch(2));  // two one-task jobs
  Millis now = 1;
  for (const Outgoing& o : jobs_in(d.outgoing(now))) d.on_result(o.worker, answer(o.message.job()), now);
  // both are proven now; each answer waits for the other's check, and m answers nothing more
  drive(d, d.outgoing(++now), now, {"m"});
  ASSERT_TRUE(d.batch_done()) << "queue " << d.view(0).queue_depth;
  EXPECT_GE(d.view(0).coordinator_checks, 1);
  EXPECT_LT(now, 1 + 3 * 1000) << "about one lease";
  expect_task_order(d.take_results());
}

TEST(Dispatcher, AJobNoOtherWorkerCanCheckIsCheckedByTheCoordinator) {
  Dispatcher d(checking_every_job());
  join(d, "alone", stranger_hello("alone"), 0);
  d.start_batch(batch(4));
  Millis now = 1;
  drive(d, d.outgoing(now), now);
  ASSERT_TRUE(d.batch_done());
  EXPECT_GT(d.view(0).coordinator_checks, 0);
  EXPECT_EQ(d.view(0).verified_jobs, d.view(0).coordinator_checks);
  expect_task_order(d.take_results());
}

TEST(Dispatcher, WorkersThatJoinWhileJobsWaitForACheckTakeThemWhenPastProbation) {
  for (const bool past_probation : {false, true}) {
    Dispatcher d(checking_every_job());
    join(d, "a", stranger_hello("a"), 0);
    join(d, "b", stranger_hello("b"), 0);
    d.start_batch(batch(2));  // one task a job
    Millis now = 1;
    for (const Outgoing& o : jobs_in(d.outgoing(now))) d.on_result(o.worker, answer(o.message.job()), now);
    // a's and b's answers, given on probation, wait for a witness past probation: a local worker is one, a newcomer
    // is not, and with none the coordinator checks them
    join(d, "c", past_probation ? hello() : stranger_hello("c"), now);
    drive(d, d.outgoing(++now), now);
    ASSERT_TRUE(d.batch_done());
    EXPECT_EQ(d.view(0).verified_jobs, 2);
    EXPECT_EQ(d.view(0).coordinator_checks, past_probation ? 0 : 2);
  }
}

TEST(Dispatcher, ALocalWorkersAnswersAreNotChecked) {
  Dispatcher d(checking_every_job());
  join(d, "local", hello(), 0);
  join(d, "other", stranger_hello("other"), 0);
  d.start_batch(batch(8));
  Millis now = 1;
  drive(d, d.outgoing(now), now);
  ASSERT_TRUE(d.batch_done());
  const std::vector<RolloutResult> results = d.take_results();
  expect_task_order(results);
}

TEST(Dispatcher, WhatIsReportedFinalNeverChangesWhateverTheOrderOfAnswersAndALiar) {
  // a liar among three workers, half the jobs checked, answers in a different order for each seed: a result
  // reported final (take_ready) is reported once and is the one the batch returns
  for (uint64_t seed = 0; seed < 40; ++seed) {
    DispatchSettings s = settings();
    s.verify_fraction = 0.5;
    s.verify_secret = seed;
    Dispatcher d(s);
    for (const char* id : {"liar", "b", "c"}) join(d, id, stranger_hello(id), 0);
    d.start_batch(batch(24));
    RandomStream order(stream_key(seed, "answer-order"));
    std::vector<Outgoing> held;
    std::vector<std::optional<double>> reported(24);
    Millis now = 1;
    for (int round = 0; round < 2000 && !d.batch_done() && !d.failure(); ++round) {
      for (Outgoing& o : jobs_in(d.outgoing(now))) held.push_back(std::move(o));
      if (!held.empty()) {  // one held job answered, chosen at random
        const size_t k =
            held.size() == 1 ? 0 : static_cast<size_t>(order.uniform_int(0, static_cast<int64_t>(held.size()) - 1));
        const Outgoing o = held[k];
        held.erase(held.begin() + static_cast<std::ptrdiff_t>(k));
        wire::Result r = answer(o.message.job());
        if (o.worker == "liar")
          for (wire::TaskResult& t : *r.mutable_results()) t.set_total_reward(t.total_reward() + 1);
        d.on_result(o.worker, r, now);
      }
      for (const Dispatcher::CoordinatorCheck& check : d.take_coordinator_checks())
        d.settle_by_coordinator(check.batch_id, check.job_id, coordinators_results(check));
      for (const Dispatcher::Ready& ready : d.take_ready()) {
        for (size_t i = 0; i < ready.results.size(); ++i) {
          ASSERT_FALSE(reported[ready.first + i])
              << "seed " << seed << ": task " << ready.first + i << " reported twice";
          reported[ready.first + i] = ready.results[i].total_reward;
        }
      }
      now += 10;
      for (const WorkerView& w : d.workers()) d.heard_from(w.id, now);
    }
    ASSERT_FALSE(d.failure()) << "seed " << seed << ": " << *d.failure();
    ASSERT_TRUE(d.batch_done()) << "seed " << seed << ": queue " << d.view(0).queue_depth << ", in flight "
                                << d.view(0).in_flight_jobs << ", workers " << d.worker_count() << ", held "
                                << held.size() << ", wrong " << d.referee().refusals().size() << " "
                                << (d.referee().refusals().empty() ? "" : d.referee().refusals()[0].name);
    for (const Dispatcher::Ready& ready : d.take_ready())
      for (size_t i = 0; i < ready.results.size(); ++i) reported[ready.first + i] = ready.results[i].total_reward;
    const std::vector<RolloutResult> results = d.take_results();
    for (size_t t = 0; t < results.size(); ++t) {
      ASSERT_TRUE(reported[t]) << "seed " << seed << ": task " << t << " never reported";
      EXPECT_EQ(*reported[t], results[t].total_reward) << "seed " << seed << ": task " << t;
    }
  }
}

TEST(Dispatcher, AnErrorStopsTheRunWhenTheWorkersThatRefusedAreAllThatIsLeft) {
  Dispatcher d(settings());
  join(d, "p", hello(), 0);
  join(d, "q", hello(), 0);
  d.start_batch(batch(1));
  const std::vector<Outgoing> jobs = jobs_in(d.outgoing(1));
  ASSERT_EQ(jobs.size(), 1u);
  wire::Result refusal;
  refusal.set_job_id(jobs[0].message.job().job_id());
  refusal.set_error("task refused");
  d.on_result(jobs[0].worker, refusal, 2);
  EXPECT_FALSE(d.failure());
  d.remove_worker(jobs[0].worker == "p" ? "q" : "p", /*died=*/false);  // the other leaves before it answers
  d.outgoing(3);
  ASSERT_TRUE(d.failure()) << "the job would wait forever";
  EXPECT_TRUE(contains(*d.failure(), "1 of the 1 proven workers")) << *d.failure();
}

// Workers that share one CURVE key (Compose's one worker key pair) are one witness: the error rule asks two
// witnesses, or the only one connected, so their error stops the run rather than leave the job to no one.
TEST(Dispatcher, AnErrorStopsTheRunWhenEveryWorkerSharesOneKey) {
  Dispatcher d(settings());
  for (const char* id : {"a", "b", "c"}) join(d, id, stranger_hello(id), 0, "shared-key");
  d.start_batch(batch(3));  // proven by answering
  Millis now = 1;
  for (int round = 0; round < 10 && !d.batch_done(); ++round, ++now)
    for (const Outgoing& o : jobs_in(d.outgoing(now))) d.on_result(o.worker, answer(o.message.job()), now);
  ASSERT_TRUE(d.batch_done());
  d.take_results();
  d.start_batch(batch(1));
  for (int round = 0; round < 10 && !d.failure(); ++round, ++now) {
    for (const Outgoing& o : jobs_in(d.outgoing(now))) {
      wire::Result refusal;
      refusal.set_job_id(o.message.job().job_id());
      refusal.set_error("task refused");
      d.on_result(o.worker, refusal, now);
    }
  }
  ASSERT_TRUE(d.failure()) << "the job would wait forever: every worker refused it";
  EXPECT_TRUE(contains(*d.failure(), "task refused")) << *d.failure();
}

TEST(Dispatcher, APeerSayingItLacksTheThetaOfAJobSentWithItIsRefusedTheJob) {
  Dispatcher d(settings());
  join(d, "peer", stranger_hello("peer"), 0);
  join(d, "real", hello(), 0);
  d.start_batch(batch(8));
  Millis now = 1;
  std::vector<Outgoing> for_real;
  for (int round = 0; round < 3; ++round) {
    for (const Outgoing& o : jobs_in(d.outgoing(now++))) {
      if (o.worker == "real") {
        for_real.push_back(o);
        continue;
      }
      wire::Result missing;
      missing.set_job_id(o.message.job().job_id());
      missing.set_error("no θ");
      missing.set_missing_theta(true);
      d.on_result("peer", missing, now);
    }
  }
  EXPECT_EQ(d.referee().counts().demoted, 1) << "believed once, then an error";
  drive(d, for_real, now);
  EXPECT_TRUE(d.batch_done());
}

TEST(Dispatcher, AFailedSendCountsTheWorkerAsLost) {
  Dispatcher d(settings());
  join(d, "a", hello(), 0);
  d.lose_worker("a");
  d.lose_worker("a");  // once
  EXPECT_EQ(d.view(0).workers_lost, 1);
  EXPECT_EQ(d.worker_count(), 0u);
}

WorkerView view_of(const Dispatcher& d, const WorkerId& id) {
  for (const WorkerView& w : d.workers())
    if (w.id == id) return w;
  ADD_FAILURE() << "no worker " << id;
  return WorkerView{};
}

// Batches of one-task jobs, each driven to its end (drive()), until `until` holds or ten have run.
template <typename Until>
void run_batches(Dispatcher& d, Millis& now, Until until) {
  for (int b = 0; b < 10 && !until(); ++b) {
    d.start_batch(batch(20));
    drive(d, d.outgoing(now), now);
    ASSERT_TRUE(d.batch_done());
    expect_task_order(d.take_results());
  }
}

// A worker that joins once the others are past probation, with almost nothing drawn for a check: each of its
// answers on probation is compared with another's — the proven worker's that checks the answer held, or the one
// taken from a proven worker that backed up its trial and answered first — so its probation ends within a few jobs
// of its own, not after about probation_checks / verify_fraction of them.
TEST(Dispatcher, AWorkerJoiningAfterTheOthersAreProvenLeavesProbationWithinAFewOfItsJobs) {
  DispatchSettings s = one_task_jobs();
  s.verify_fraction = 1e-12;
  s.probation_checks = 5;
  Dispatcher d(s);
  for (const char* id : {"a", "b"}) join(d, id, stranger_hello(id), 0);
  Millis now = 1;
  run_batches(d, now,
              [&] { return view_of(d, "a").trust == Trust::kProven && view_of(d, "b").trust == Trust::kProven; });
  ASSERT_EQ(view_of(d, "a").trust, Trust::kProven);
  ASSERT_EQ(view_of(d, "b").trust, Trust::kProven);

  join(d, "late", stranger_hello("late"), now);
  EXPECT_EQ(view_of(d, "late").trust, Trust::kTrial);
  run_batches(d, now, [&] { return view_of(d, "late").trust == Trust::kProven; });
  const WorkerView late = view_of(d, "late");
  EXPECT_EQ(late.trust, Trust::kProven);
  EXPECT_GE(late.checks_passed, 5);
  EXPECT_LE(late.probation_answers, 5 + 1) << "probation took " << late.probation_answers << " of its jobs";
  EXPECT_LE(late.jobs_done, 5 + 3) << "probation took " << late.jobs_done << " of its jobs";
  EXPECT_LE(late.answers_taken_unchecked, late.answers_taken);
  EXPECT_FALSE(take_rollback(d));
}

// Proven workers p and q, past probation; a newcomer n whose trial p backs up and answers first. n's answer, come
// late, is compared with the results taken from p: alike, both pass a check; different, the task goes out again and
// a third answer (q's) decides, refusing n.
TEST(Dispatcher, ALateAnswerIsComparedWithTheResultsTaken) {
  for (const bool lies : {false, true}) {
    DispatchSettings s = one_task_jobs();
    s.verify_fraction = 1e-12;
    s.probation_checks = 0;  // p and q are proven by their first answers
    Dispatcher d(s);
    for (const char* id : {"p", "q"}) join(d, id, stranger_hello(id), 0);
    Millis now = 1;
    run_batches(d, now, [&] { return view_of(d, "p").trust == Trust::kProven; });
    join(d, "n", stranger_hello("n"), now);
    d.start_batch(batch(3));
    std::vector<Outgoing> sent = jobs_in(d.outgoing(now));
    std::optional<Outgoing> trial;
    uint64_t backed_up = 0;
    for (const Outgoing& o : sent) {
      if (o.worker == "n") trial = o;
      if (o.worker == "p" && trial && o.message.job().job_id() == trial->message.job().job_id())
        backed_up = o.message.job().job_id();
    }
    ASSERT_TRUE(trial);
    ASSERT_EQ(backed_up, trial->message.job().job_id()) << "p backs up the newcomer's trial at once";
    for (const Outgoing& o : sent)  // p first; q's job stays open, so the batch runs on
      if (o.worker == "p") d.on_result(o.worker, answer(o.message.job()), now);
    const int64_t p_checks = view_of(d, "p").checks_passed;
    d.on_result("n", answer_lying_as(*trial, lies ? "n" : ""), now);  // late
    for (const Outgoing& o : sent)
      if (o.worker == "q") d.on_result(o.worker, answer(o.message.job()), now);
    if (!lies) {
      EXPECT_EQ(view_of(d, "n").checks_passed, 1);
      EXPECT_EQ(view_of(d, "p").checks_passed, p_checks + 1);
      ASSERT_TRUE(d.batch_done());
    } else {
      EXPECT_FALSE(d.batch_done()) << "the task taken from p is disputed";
      drive(d, d.outgoing(now), now, {"n"});
      ASSERT_TRUE(d.batch_done());
      ASSERT_EQ(d.referee().refusals().size(), 1u);
      EXPECT_EQ(d.referee().refusals()[0].name, "n");
      ASSERT_EQ(d.view(now).refused.size(), 1u);
      EXPECT_EQ(d.view(now).refused[0].trust, Trust::kRefused);
    }
    expect_task_order(d.take_results());
  }
}

// A liar that joins late and lies from its first answer: its answers are compared with proven workers', and it is
// refused, whichever comes first.
TEST(Dispatcher, ALateJoinerThatLiesIsRefused) {
  DispatchSettings s = one_task_jobs();
  s.verify_fraction = 1e-12;
  s.probation_checks = 2;
  Dispatcher d(s);
  for (const char* id : {"a", "b", "c"}) join(d, id, stranger_hello(id), 0);
  Millis now = 1;
  run_batches(d, now, [&] { return view_of(d, "c").trust == Trust::kProven; });
  join(d, "liar", stranger_hello("liar"), now);
  for (int b = 0; b < 5 && d.referee().refusals().empty(); ++b) {
    d.start_batch(batch(20));
    std::vector<Outgoing> out = d.outgoing(now);
    for (int round = 0; round < 1000 && !d.batch_done() && !d.failure(); ++round) out = answer_round(d, out, now);
    ASSERT_TRUE(d.batch_done());
    expect_task_order(d.take_results());
  }
  ASSERT_EQ(d.referee().refusals().size(), 1u);
  EXPECT_EQ(d.referee().refusals()[0].name, "liar");
  EXPECT_FALSE(take_rollback(d)) << "none of its answers became final unchecked";
}

// A worker found wrong is refused with its CURVE key: every other connection holding the key is refused at once,
// told why and shown as refused, its Hellos refused from then on; the key is handed to the caller once; a worker of
// another key is not touched.
TEST(Dispatcher, AWorkerFoundWrongTakesEveryConnectionOfItsKeyWithIt) {
  Dispatcher d(checking_every_job());
  join(d, "liar", stranger_hello("liar"), 0, "key-k");
  join(d, "twin", stranger_hello("twin"), 0, "key-k");
  join(d, "b", stranger_hello("b"), 0, "key-b");
  d.start_batch(batch(30));
  Millis now = 1;
  std::vector<Outgoing> out = d.outgoing(now);
  bool told = false;
  std::vector<std::string> keys;
  for (int round = 0; round < 1000 && d.referee().refusals().empty(); ++round) out = answer_round(d, out, now);
  for (const std::string& key : d.take_refused_keys()) keys.push_back(key);
  for (const Outgoing& o : out)
    told = told ||
           (o.worker == "twin" && o.message.has_refused() &&
            o.message.refused().reason() == "this worker holds the CURVE key of a worker refused for wrong results");
  EXPECT_TRUE(told);
  EXPECT_EQ(keys, std::vector<std::string>{"key-k"});
  EXPECT_TRUE(d.take_refused_keys().empty()) << "handed over once";
  EXPECT_FALSE(connected(d, "twin"));
  EXPECT_TRUE(connected(d, "b"));
  const wire::CoordinatorMessage again = d.on_hello("new-id", stranger_hello("third"), now, "key-k");
  ASSERT_TRUE(again.has_refused());
  EXPECT_TRUE(contains(again.refused().reason(), "CURVE key")) << again.refused().reason();
  EXPECT_TRUE(d.on_hello("twin", stranger_hello("twin"), now).has_refused());
  ASSERT_EQ(d.referee().refusals().size(), 2u);
  EXPECT_EQ(d.referee().refusals()[0].name, "liar");
  EXPECT_EQ(d.referee().refusals()[1].name, "twin");
  EXPECT_TRUE(contains(d.referee().refusals()[1].why, "CURVE key"));
  const DispatchView view = d.view(now);
  ASSERT_EQ(view.refused.size(), 2u);
  EXPECT_EQ(view.refused[1].id, "twin");
  EXPECT_EQ(view.refused[1].trust, Trust::kRefused);
}
}  // namespace

TEST(Dispatcher, AWorkerOnProbationHasEveryAnswerCheckedUntilItPassedEnoughChecks) {
  DispatchSettings s = settings();
  s.verify_fraction = 1e-12;  // after probation, practically nothing is checked
  s.probation_checks = 3;
  Dispatcher d(s);
  for (const char* id : {"a", "b"}) join(d, id, stranger_hello(id), 0);
  d.start_batch(batch(40));  // one task a job (two threads)
  Millis now = 1;
  drive(d, d.outgoing(now), now);
  ASSERT_TRUE(d.batch_done());
  for (const WorkerView& w : d.workers()) {
    EXPECT_TRUE(w.proven) << w.id;
    EXPECT_GE(w.checks_passed, 3) << w.id;
  }
  // each check passes at least one answer given on probation, and none is checked twice; after probation nothing
  // is checked. At first neither is past probation, and answers on probation never confirm each other (rule 2):
  // the coordinator checks those
  int64_t probation_answers = 0;
  for (const WorkerView& w : d.workers()) probation_answers += w.probation_answers;
  EXPECT_GE(d.view(0).verified_jobs, 3);
  EXPECT_LE(d.view(0).verified_jobs, probation_answers);
  EXPECT_GE(d.view(0).coordinator_checks, 1);
  expect_task_order(d.take_results());
  EXPECT_FALSE(take_rollback(d));
}

TEST(Dispatcher, ALiarPastItsProbationIsCaughtAndTheRunAskedToGoBackToBeforeItsUncheckedAnswers) {
  // a liar that answers honestly while any worker is on probation, then lies on every job of the next batches; a fifth
  // of the jobs checked: in some secrets' draws an unchecked lie of an earlier batch became final before the liar was
  // caught
  int rollbacks = 0;
  for (uint64_t secret = 0; secret < 40; ++secret) {
    DispatchSettings s = settings();
    s.verify_fraction = 0.2;
    s.verify_secret = secret;
    s.probation_checks = 2;
    Dispatcher d(s);
    for (const char* id : {"liar", "b", "c"}) join(d, id, stranger_hello(id), 0);
    Millis now = 1;
    std::optional<uint64_t> first_unchecked_final;  // the first batch in which a lie was reported final
    for (int b = 0; b < 6 && d.referee().refusals().empty(); ++b) {
      // from the first batch that starts with every worker past probation: none of its answers is held for a check
      const std::vector<WorkerView> workers = d.workers();
      const bool lying = std::all_of(workers.begin(), workers.end(),
                                     [&](const WorkerView& w) { return w.checks_passed >= s.probation_checks; });
      d.start_batch(batch(12));
      std::vector<Outgoing> out = d.outgoing(now);
      for (int round = 0; round < 1000 && !d.batch_done() && !d.failure(); ++round) {
        for (const Outgoing& o : jobs_in(out))
          d.on_result(o.worker, lying ? answer_lying_as(o, "liar") : answer(o.message.job()), now);
        for (const Dispatcher::CoordinatorCheck& check : d.take_coordinator_checks())
          d.settle_by_coordinator(check.batch_id, check.job_id, coordinators_results(check));
        now += 10;
        for (const WorkerView& w : d.workers()) d.heard_from(w.id, now);
        out = d.outgoing(now);
      }
      ASSERT_TRUE(d.batch_done()) << "secret " << secret;
      d.take_ready();
      const std::vector<RolloutResult> results = d.take_results();
      bool lie = false;
      for (size_t i = 0; i < results.size(); ++i) lie = lie || results[i].total_reward != double(i);
      if (lie && !first_unchecked_final) first_unchecked_final = d.batch_id();
    }
    const std::optional<uint64_t> rollback = take_rollback(d);
    if (first_unchecked_final) {
      // a lie became final: the liar must have been caught later (it lies on every job), and the run sent back
      ASSERT_EQ(d.referee().refusals().size(), 1u) << "secret " << secret;
      ASSERT_TRUE(rollback) << "secret " << secret;
      EXPECT_LE(*rollback, *first_unchecked_final) << "secret " << secret;
      rollbacks += 1;
    }
    EXPECT_FALSE(take_rollback(d)) << "asked once";
  }
  EXPECT_GT(rollbacks, 0) << "no secret let a lie become final before the liar was caught";
}

}  // namespace poet
