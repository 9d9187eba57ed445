// Tests coordinator/trust/referee.cpp: each event of verification turned into effects — answers held, taken and
// found wrong, a key's connections as one witness and refused together, errors, late answers reopened, the
// coordinator's own checks, leases and trials run out, deaths, and the records kept across a batch.
#include "coordinator/trust/referee.h"

#include <gtest/gtest.h>

#include <map>

#include "answers.h"

namespace poet {
namespace {

using testing::returns;

// Every answer of a worker not local checked (all jobs chosen), probation of one check.
Referee checking() { return Referee({1.0, 42, 1}); }

// The standings a referee handed out, by worker: the events name a worker by its standing.
class Joined {
 public:
  explicit Joined(Referee& referee) : referee_(referee) {}
  const Standing& operator()(const WorkerId& id, const std::string& key = "", bool local = false) {
    return *(standings_[id] = &referee_.joined(id, "worker-" + id, key, local));
  }
  const Standing& operator[](const WorkerId& id) const { return *standings_.at(id); }

 private:
  Referee& referee_;
  std::map<WorkerId, const Standing*> standings_;
};

TEST(Referee, AnAnswerOnProbationIsHeldUntilAnotherWitnessConfirmsItAndTheResultsAreTaken) {
  Referee referee = checking();
  Joined join(referee);
  const Standing& a = join("a", "", false);
  join("local", "", true);
  referee.opened(1, 1, 0, 2);
  const Effects held = referee.answer(1, join["a"], returns(3), 1);
  EXPECT_EQ(held.requeue, (std::vector<uint64_t>{1}));  // waits for a second witness
  EXPECT_FALSE(held.take);
  EXPECT_TRUE(a.proven);
  EXPECT_EQ(referee.job(1).answers.size(), 1u);
  const Effects taken = referee.answer(1, join["local"], returns(3), 1);
  ASSERT_TRUE(taken.take);
  EXPECT_EQ(taken.take->job, 1u);
  EXPECT_EQ(taken.take->credited, "a");
  EXPECT_TRUE(taken.take->final_now);
  EXPECT_TRUE(taken.refuse.empty());
  EXPECT_EQ(a.checks_passed, 1);
  EXPECT_EQ(referee.level(a), Trust::kProven);
  EXPECT_EQ(referee.counts().verified, 1);
}

TEST(Referee, ConnectionsOfOneKeyAreOneWitnessAndAWrongOneTakesTheKeyAndEveryConnectionOfItWithIt) {
  Referee referee = checking();
  Joined join(referee);
  join("liar", "key-k", false);
  join("twin", "key-k", false);
  join("gone", "key-k", false);
  join("honest", "key-h", false);
  join("local", "", true);
  referee.left("gone");  // a connection of the key, closed: refused all the same
  referee.opened(1, 1, 0, 2);
  EXPECT_EQ(referee.answer(1, join["liar"], returns(9), 1).requeue, (std::vector<uint64_t>{1}));
  const Effects twin = referee.answer(1, join["twin"], returns(9), 1);  // the same key: no second witness
  EXPECT_FALSE(twin.take);
  EXPECT_EQ(referee.job(1).answers.size(), 1u);
  Standing twin_past_probation;
  twin_past_probation.witness = "key-k";
  twin_past_probation.proven = true;
  twin_past_probation.checks_passed = 1;
  EXPECT_EQ(referee.may_take(referee.job(1), "twin", twin_past_probation), Eligibility::kNo);

  const Effects decided = referee.answer(1, join["local"], returns(1), 1);  // a local worker decides at once
  ASSERT_TRUE(decided.take);
  EXPECT_EQ(decided.take->credited, "local");
  ASSERT_EQ(decided.refuse.size(), 3u);
  EXPECT_EQ(decided.refuse[0].worker, "liar");
  EXPECT_EQ(decided.refuse[0].why, "returned results that two other workers did not");
  for (size_t i = 1; i < 3; ++i) {
    EXPECT_TRUE(decided.refuse[i].worker == "twin" || decided.refuse[i].worker == "gone") << decided.refuse[i].worker;
    EXPECT_EQ(decided.refuse[i].why, "holds the CURVE key of a worker refused for wrong results");
  }
  EXPECT_EQ(decided.refuse_keys, (std::vector<std::string>{"key-k"}));  // once
  ASSERT_EQ(referee.refusals().size(), 3u);
  EXPECT_EQ(referee.refusals()[0].name, "worker-liar");
  EXPECT_EQ(referee.hello_refused("liar", ""), "this worker was refused for wrong results");
  EXPECT_EQ(referee.hello_refused("new", "key-k"),
            "this worker holds the CURVE key of a worker refused for wrong results");
  EXPECT_FALSE(referee.hello_refused("new", "key-h"));
  EXPECT_FALSE(referee.hello_refused("honest", "key-h"));
}

TEST(Referee, AWrongAnswerHeldIsForgottenAndItsJobsPutBack) {
  Referee referee = checking();
  Joined join(referee);
  join("liar", "", false);
  join("b", "", false);
  join("local", "", true);
  referee.opened(1, 1, 0, 1);
  referee.opened(2, 1, 1, 2);
  referee.answer(1, join["liar"], returns(5), 1);
  referee.answer(2, join["liar"], returns(6), 1);
  referee.answer(1, join["b"], returns(4), 1);  // two that differ: a third witness decides
  const Effects decided = referee.answer(1, join["local"], returns(4), 1);
  ASSERT_EQ(decided.refuse.size(), 1u);
  EXPECT_EQ(decided.refuse[0].worker, "liar");
  // its answer to job 2 is worth nothing: the job waits for others'
  EXPECT_EQ(decided.requeue, (std::vector<uint64_t>{1, 2}));
  EXPECT_TRUE(referee.job(2).answers.empty());
  EXPECT_TRUE(decided.refuse_keys.empty());  // without CURVE no key
}

TEST(Referee, AnErrorOfAWorkerNotProvenPutsTheJobBackAndTwoProvenWorkersStopTheRun) {
  Referee referee = checking();
  Joined join(referee);
  join("fresh", "", false);
  join("p1", "", true);
  join("p2", "", true);
  referee.opened(1, 1, 0, 1);
  const Effects fresh = referee.error(1, join["fresh"]);
  EXPECT_EQ(fresh.error, ErrorVerdict::kFromUnproven);
  EXPECT_EQ(fresh.requeue, (std::vector<uint64_t>{1}));
  EXPECT_EQ(referee.counts().demoted, 1);
  EXPECT_EQ(referee.error(1, join["p1"]).error, ErrorVerdict::kRetry);
  const Effects stop = referee.error(1, join["p2"]);
  EXPECT_EQ(stop.error, ErrorVerdict::kStop);
  EXPECT_TRUE(stop.requeue.empty());
  EXPECT_EQ(referee.job(1).refusing.size(), 2u);
  EXPECT_TRUE(referee.refused_by_enough(1));
}

TEST(Referee, ThreeAnswersNoneConfirmedGoToTheCoordinatorWhoseAnswerDecides) {
  Referee referee = checking();
  Joined join(referee);
  for (const char* id : {"a", "b", "c"}) join(id);
  referee.opened(7, 1, 0, 1);
  referee.answer(7, join["a"], returns(1), 1);
  referee.answer(7, join["b"], returns(2), 1);
  const Effects third = referee.answer(7, join["c"], returns(3), 1);
  EXPECT_EQ(third.to_coordinator, (std::vector<uint64_t>{7}));
  EXPECT_TRUE(third.requeue.empty());  // not sent out again
  const Effects settled = referee.coordinator_answer(7, returns(2), 1);
  ASSERT_TRUE(settled.take);
  EXPECT_EQ(settled.take->credited, kCoordinatorAnswer);
  ASSERT_EQ(settled.refuse.size(), 2u);
  EXPECT_EQ(settled.refuse[0].worker, "a");
  EXPECT_EQ(settled.refuse[1].worker, "c");
  EXPECT_EQ(referee.counts().coordinator_checks, 1);
}

TEST(Referee, AJobStuckWithAnswersNoOneCanCheckGoesToTheCoordinatorOnce) {
  Referee referee = checking();
  Joined join(referee);
  join("a", "", false);
  referee.opened(3, 1, 0, 1);
  referee.answer(3, join["a"], returns(1), 1);
  EXPECT_TRUE(referee.stuck(3, /*queued=*/true, /*checker_connected=*/true, 0, 10, 1000).to_coordinator.empty());
  EXPECT_EQ(referee.stuck(3, true, false, 0, 10, 1000).to_coordinator, (std::vector<uint64_t>{3}));
  EXPECT_TRUE(referee.stuck(3, true, false, 0, 20, 1000).to_coordinator.empty()) << "handed over once";
}

TEST(Referee, ALateAnswerThatDiffersReopensTheTasksHoldingBothAnswers) {
  Referee referee = checking();
  Joined join(referee);
  join("taken", "", false);
  join("late", "", false);
  const std::vector<RolloutResult> taken = returns(1);
  const Effects reopen = referee.late_answer("late", returns(2), "taken", taken, /*taken_final=*/false, 4, 6, 1);
  ASSERT_TRUE(reopen.reopen);
  EXPECT_EQ(reopen.reopen->begin, 4u);
  EXPECT_EQ(reopen.reopen->end, 6u);
  ASSERT_EQ(reopen.reopen->held.size(), 2u);
  const JobTrust& job = referee.opened(9, 1, 4, 6, reopen.reopen->held);
  EXPECT_EQ(job.answers.size(), 2u);  // a third witness decides
  EXPECT_TRUE(referee.late_answer("gone", returns(2), "taken", taken, false, 4, 6, 1).refuse.empty())
      << "a worker not connected: nothing";
  const Effects against_final = referee.late_answer("late", returns(2), "taken", taken, /*taken_final=*/true, 4, 6, 1);
  ASSERT_EQ(against_final.refuse.size(), 1u);
  EXPECT_EQ(against_final.refuse[0].worker, "late");
}

TEST(Referee, LeasesAndTrialsRunOutDemoteWorkersNotProvenAndOnlyAProvenWorkersDeathCounts) {
  Referee referee = checking();
  Joined join(referee);
  const Standing& fresh = join("fresh", "", false);
  const Standing& quiet = join("quiet", "", false);
  const Standing& nonsense = join("nonsense", "", false);
  join("local", "", true);
  referee.opened(1, 1, 0, 1);
  EXPECT_FALSE(referee.died_with(1, join["fresh"]));
  EXPECT_TRUE(referee.job(1).tainted);
  EXPECT_TRUE(referee.died_with(1, join["local"]));
  referee.lease_ran_out(1, join["fresh"]);
  EXPECT_TRUE(fresh.demoted);
  EXPECT_TRUE(referee.job(1).failed.contains("fresh"));
  EXPECT_FALSE(referee.trial_ran_out(join["quiet"], 100, false, 500, 1000));
  EXPECT_TRUE(referee.trial_ran_out(join["quiet"], 100, false, 1100, 1000));
  EXPECT_TRUE(quiet.demoted);
  referee.sent_nonsense(join["nonsense"]);
  EXPECT_TRUE(nonsense.demoted);
  EXPECT_EQ(referee.counts().demoted, 3);
  EXPECT_EQ(referee.jobs_at_once(nonsense, false, 2), 0u);
}

TEST(Referee, ADepartedWorkersAnswerIsJudgedUntilItsBatchEndsAndGoingBackIsTakenOnce) {
  Referee referee({0.01, 42, 0});  // past probation at once: few jobs checked
  Joined join(referee);
  join("past", "", false);
  join("b", "", false);
  uint64_t batch = 1;
  while (referee.opened(1, batch, 0, 1).chosen) ++batch;  // a job the secret did not choose
  const Effects unchecked = referee.answer(1, join["past"], returns(1), batch);
  ASSERT_TRUE(unchecked.take);
  EXPECT_FALSE(unchecked.take->final_now);  // held back until the batch is whole
  referee.left("past");
  // in a later batch a local worker's late answer differs from it: the worker is refused, and the run goes back to
  // before the batch of its unchecked answer
  join("local", "", true);
  const std::vector<RolloutResult> taken = returns(1);
  const Effects wrong = referee.late_answer("local", returns(2), "past", taken, false, 0, 1, batch + 1);
  ASSERT_EQ(wrong.refuse.size(), 1u);
  EXPECT_EQ(wrong.refuse[0].worker, "past");
  EXPECT_EQ(referee.refusals()[0].name, "worker-past");  // its name, though it left
  EXPECT_EQ(referee.rollback_asked(), batch);
  referee.went_back(batch - 1);
  EXPECT_FALSE(referee.rollback_asked());
  EXPECT_EQ(referee.counts().rollbacks, 1);
  referee.batch_ended();
  referee.batch_started();  // the departed worker's record is gone
  referee.opened(2, batch + 2, 0, 1);
  EXPECT_TRUE(referee.late_answer("past", returns(1), "b", taken, false, 0, 1, batch + 2).refuse.empty());
}

}  // namespace
}  // namespace poet
