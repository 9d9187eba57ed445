// Tests coordinator/trust/worker_trust.cpp: the decisions trust hands the dispatcher as values — who may take a
// job, what a death, a lease run out, an error or an answer settles, the coordinator's own checks, and going back.
#include "coordinator/trust/worker_trust.h"

#include <gtest/gtest.h>

#include "answers.h"

namespace poet {
namespace {

using testing::returns;

// Verification on every job not chosen by the secret: 1 % of jobs chosen, probation of two checks.
WorkerTrust checking() { return WorkerTrust({0.01, 42, 2}); }

Standing proven() {
  Standing s;
  s.proven = true;
  s.checks_passed = 2;  // past probation
  return s;
}

TEST(WorkerTrust, ANewcomerIsOnTrialUnlessLocalAndHoldsOneJobUntilProvenAndPastProbation) {
  WorkerTrust trust = checking();
  Standing remote = trust.newcomer({}, {}, false), local = trust.newcomer({}, {}, true);
  EXPECT_EQ(trust.level(remote), Trust::kTrial);
  EXPECT_EQ(trust.level(local), Trust::kProven);
  EXPECT_EQ(trust.jobs_at_once(remote, false, 2), 1u);
  EXPECT_EQ(trust.jobs_at_once(local, false, 2), 2u);
  trust.answered(remote, /*counted=*/true);
  EXPECT_EQ(trust.level(remote), Trust::kProbation);
  EXPECT_EQ(remote.probation_answers, 1);
  EXPECT_EQ(trust.jobs_at_once(remote, false, 2), 1u);
  trust.passed_check(remote);
  trust.passed_check(remote);
  EXPECT_EQ(trust.level(remote), Trust::kProven);
  EXPECT_EQ(trust.jobs_at_once(remote, false, 2), 2u);
  trust.answered(remote, /*counted=*/true);
  EXPECT_EQ(remote.probation_answers, 1);  // past probation: no longer counted
  EXPECT_EQ(trust.level(WorkerTrust({0, 0, 5}).newcomer({}, {}, false)), Trust::kTrial);
}

TEST(WorkerTrust, AWorkerNotProvenHoldsNothingMoreWhileItsTrialIsUnansweredAndIsDemotedALeaseOn) {
  WorkerTrust trust = checking();
  Standing fresh = trust.newcomer({}, {}, false);
  EXPECT_EQ(trust.jobs_at_once(fresh, /*trial_unanswered=*/true, 2), 0u);
  EXPECT_FALSE(trust.trial_ran_out(fresh, 100, /*holding=*/true, 1000, 500));  // it still holds it: the lease says
  EXPECT_FALSE(trust.trial_ran_out(fresh, 100, false, 599, 500));
  EXPECT_FALSE(trust.trial_ran_out(fresh, std::nullopt, false, 10'000, 500));  // never sent one
  EXPECT_TRUE(trust.trial_ran_out(fresh, 100, false, 600, 500));
  EXPECT_TRUE(fresh.demoted);
  EXPECT_FALSE(trust.trial_ran_out(fresh, 100, false, 700, 500));  // once
  EXPECT_EQ(trust.demoted(), 1);
  EXPECT_EQ(trust.jobs_at_once(fresh, false, 2), 0u);  // demoted: nothing
  EXPECT_EQ(trust.jobs_at_once(proven(), true, 2), 2u);
}

TEST(WorkerTrust, ATaintedJobGoesToAWorkerNotProvenOnlyWhenNoProvenOneCanAndNeverAsACheck) {
  WorkerTrust trust = checking();
  JobTrust job;
  const Standing fresh = trust.newcomer({}, {}, false);
  EXPECT_EQ(trust.may_take(job, "new", fresh), Eligibility::kYes);
  job.tainted = true;
  EXPECT_EQ(trust.may_take(job, "new", fresh), Eligibility::kIfNoProvenCan);
  EXPECT_EQ(trust.may_take(job, "old", proven()), Eligibility::kYes);
  job.failed.insert("old");
  EXPECT_EQ(trust.may_take(job, "old", proven()), Eligibility::kNo);  // not sent to it again
  job.answers.push_back({"other", returns(1)});
  EXPECT_EQ(trust.may_take(job, "new", fresh), Eligibility::kNo);  // a check: one that never answered may sit on it
  EXPECT_EQ(trust.may_take(job, "other", proven()), Eligibility::kNo);  // its own answer is no check
  EXPECT_EQ(trust.may_take(job, "third", proven()), Eligibility::kYes);
}

// One witness counts once wherever connections are counted: in the error rule, against final results, in what a
// refusal forgets; a local worker is its own witness, whatever key it shares.
TEST(WorkerTrust, AKeysConnectionsCountOnceAndALocalWorkerIsItsOwnWitness) {
  WorkerTrust trust = checking();
  EXPECT_EQ(trust.newcomer("local", "key-k", true).witness, "local");
  Standing k1 = proven(), k2 = proven(), other = proven();
  k1.witness = k2.witness = "key-k";
  JobTrust failing;
  EXPECT_EQ(trust.error(failing, "k1", k1, 3), ErrorVerdict::kRetry);
  EXPECT_EQ(trust.error(failing, "k2", k2, 3), ErrorVerdict::kRetry);  // the same key: still one
  EXPECT_EQ(trust.error(failing, "other", other, 3), ErrorVerdict::kStop);

  Settlement twin = trust.late_answer({"k1", returns(1), "key-k"}, /*taken_final=*/true, {"k2", returns(1), "key-k"},
                                      false);
  EXPECT_EQ(twin.kind, Settlement::Kind::kStands);
  EXPECT_TRUE(twin.passed.empty());  // no check passed by its own key
  Settlement twin_differs =
      trust.late_answer({"k1", returns(1), "key-k"}, true, {"k2", returns(2), "key-k"}, false);
  EXPECT_EQ(twin_differs.wrong, (std::vector<WorkerId>{"k2"}));

  JobTrust held;
  held.answers = {{"k2", returns(1), "key-k"}, {"other", returns(2)}};
  EXPECT_TRUE(trust.forget_answers_of(held, "k1", "key-k"));  // k1 refused: its key's answers go too
  ASSERT_EQ(held.answers.size(), 1u);
  EXPECT_EQ(held.answers[0].worker, "other");
}

TEST(WorkerTrust, AJobHoldingAnAnswerGoesToAnotherWitnessPastProbationWhereTheRulesAskIt) {
  WorkerTrust trust = checking();
  const Standing twin = trust.newcomer("twin", "key-k", false);
  EXPECT_EQ(twin.witness, "key-k");
  EXPECT_EQ(trust.newcomer("plain", {}, false).witness, "plain");  // without CURVE, its routing id
  Standing past = proven();
  past.witness = "key-k";
  Standing probation = trust.newcomer("newcomer", {}, false);
  trust.answered(probation, true);
  Standing probation2 = trust.newcomer("newcomer2", {}, false);
  trust.answered(probation2, true);
  Standing other = proven();
  JobTrust job;
  job.answers.push_back(trust.answer_of("first", past, returns(1)));         // key-k's answer, past probation
  EXPECT_EQ(trust.may_take(job, "second", past), Eligibility::kNo);          // another connection of key-k: no witness
  EXPECT_EQ(trust.may_take(job, "newcomer", probation), Eligibility::kYes);  // may confirm a proven answer
  EXPECT_EQ(trust.may_take(job, "other", other), Eligibility::kYes);
  JobTrust on_probation;
  on_probation.answers.push_back(trust.answer_of("newcomer", probation, returns(1)));
  EXPECT_TRUE(on_probation.answers[0].probation);
  EXPECT_EQ(trust.may_take(on_probation, "newcomer2", probation2), Eligibility::kNo);  // rule 2
  EXPECT_EQ(trust.may_take(on_probation, "other", other), Eligibility::kYes);
  job.answers.push_back(trust.answer_of("newcomer", probation, returns(2)));  // a dispute
  EXPECT_EQ(trust.may_take(job, "newcomer2", probation2), Eligibility::kNo);  // rule 3
  EXPECT_EQ(trust.may_take(job, "other", other), Eligibility::kYes);
}

TEST(WorkerTrust, ADeathALeaseRunOutOrAnErrorOfAWorkerNotProvenTaintsTheJobAndCannotStopTheRun) {
  WorkerTrust trust = checking();
  JobTrust job;
  Standing fresh = trust.newcomer({}, {}, false);
  EXPECT_FALSE(trust.death_counts(job, fresh));
  EXPECT_TRUE(job.tainted);
  EXPECT_TRUE(trust.death_counts(job, proven()));

  JobTrust leased;
  trust.lease_ran_out(leased, "slow", fresh);
  EXPECT_TRUE(leased.tainted && leased.failed.contains("slow") && fresh.demoted);
  trust.lease_ran_out(leased, "slow", fresh);
  EXPECT_EQ(trust.demoted(), 1);  // once

  JobTrust failing;
  Standing other = trust.newcomer({}, {}, false);
  EXPECT_EQ(trust.error(failing, "peer", other, 3), ErrorVerdict::kFromUnproven);
  EXPECT_TRUE(other.demoted && failing.refusing.empty());
  Standing a = proven(), b = proven();
  EXPECT_EQ(trust.error(failing, "a", a, 3), ErrorVerdict::kRetry);  // another proven worker says
  EXPECT_EQ(trust.error(failing, "b", b, 3), ErrorVerdict::kStop);   // two agree: a real error repeats
  JobTrust alone;
  EXPECT_EQ(trust.error(alone, "a", a, 1), ErrorVerdict::kStop);  // the only proven worker connected
  EXPECT_FALSE(a.demoted);
}

TEST(WorkerTrust, AnAnswerOnProbationIsHeldUntilASecondAgreesAndBothPassACheck) {
  WorkerTrust trust = checking();
  JobTrust job = trust.new_job(1, 0, 1);
  Standing newcomer = trust.newcomer({}, {}, false);
  trust.answered(newcomer, true);
  Settlement first = trust.answer(job, "new", newcomer, returns(5), 1);
  EXPECT_EQ(first.kind, Settlement::Kind::kHold);
  ASSERT_EQ(job.answers.size(), 1u);
  Standing checker = proven();
  Settlement second = trust.answer(job, "old", checker, returns(5), 1);
  EXPECT_EQ(second.kind, Settlement::Kind::kTake);
  EXPECT_EQ(second.credited, "new");
  EXPECT_TRUE(second.final_now && second.checked && second.wrong.empty());
  EXPECT_EQ(second.passed, (std::vector<WorkerId>{"new", "old"}));
  EXPECT_EQ(second.results.size(), 2u);
  EXPECT_EQ(trust.verified(), 1);
}

TEST(WorkerTrust, TwoAnswersThatDifferWaitForAThirdWhichNamesTheWrongOneAndThreeThatDifferGoToTheCoordinator) {
  WorkerTrust trust = checking();
  Standing a = trust.newcomer({}, {}, false), b = proven(), c = proven(), d = proven();
  JobTrust job;
  EXPECT_EQ(trust.answer(job, "a", a, returns(1), 1).kind, Settlement::Kind::kHold);
  EXPECT_EQ(trust.answer(job, "b", b, returns(2), 1).kind, Settlement::Kind::kHold);
  Settlement third = trust.answer(job, "c", c, returns(2), 1);
  EXPECT_EQ(third.kind, Settlement::Kind::kTake);
  EXPECT_EQ(third.wrong, (std::vector<WorkerId>{"a"}));
  EXPECT_EQ(third.why_wrong, "returned results that two other workers did not");

  JobTrust split;
  trust.answer(split, "a", a, returns(1), 1);
  trust.answer(split, "b", b, returns(2), 1);
  EXPECT_EQ(trust.answer(split, "d", d, returns(3), 1).kind, Settlement::Kind::kCoordinator);
  EXPECT_EQ(split.answers.size(), 3u);  // all held, for the coordinator to settle
  trust.ask_coordinator(5, split);
  trust.ask_coordinator(5, split);
  EXPECT_EQ(trust.take_coordinator_jobs(), (std::vector<uint64_t>{5}));  // once

  JobTrust local_decides;
  trust.answer(local_decides, "a", a, returns(1), 1);
  Standing local = trust.newcomer({}, {}, true);
  Settlement at_once = trust.answer(local_decides, "local", local, returns(2), 1);
  EXPECT_EQ(at_once.kind, Settlement::Kind::kTake);
  EXPECT_EQ(at_once.credited, "local");
  EXPECT_EQ(at_once.wrong, (std::vector<WorkerId>{"a"}));
}

TEST(WorkerTrust, AnUncheckedAnswerIsHeldBackAndRefusingItsWorkerLaterSendsTheRunBackBeforeItsBatch) {
  WorkerTrust trust = checking();
  Standing past = proven();
  uint64_t batch = 3;
  JobTrust job;
  while ((job = trust.new_job(batch, 0, 1)).chosen) ++batch;  // a job the secret did not choose
  Settlement taken = trust.answer(job, "past", past, returns(1), batch);
  EXPECT_EQ(taken.kind, Settlement::Kind::kTake);
  EXPECT_FALSE(taken.final_now || taken.checked);  // final once the batch is whole
  EXPECT_EQ(trust.unchecked_since(), (std::vector<uint64_t>{batch}));
  EXPECT_FALSE(trust.take_rollback());
  EXPECT_TRUE(trust.refuse("past", {"worker-past", "lied"}, batch + 2));
  EXPECT_FALSE(trust.refuse("past", {"worker-past", "lied"}, batch + 2));
  EXPECT_TRUE(trust.refused("past"));
  EXPECT_EQ(trust.rollback_asked(), batch);
  EXPECT_EQ(trust.unchecked_since(), (std::vector<uint64_t>{batch}));  // a checkpoint before it must stay reachable
  EXPECT_EQ(trust.take_rollback(), batch);
  EXPECT_FALSE(trust.rollback_asked());
  EXPECT_FALSE(trust.take_rollback());  // once
  EXPECT_EQ(trust.rollbacks(), 1);

  Standing local = trust.newcomer({}, {}, true);
  Settlement from_local = trust.answer(job, "local", local, returns(1), batch);
  EXPECT_TRUE(from_local.final_now);  // a local worker's answer is final at once, never checked
  Standing anyone;
  EXPECT_TRUE(WorkerTrust({0, 0, 5}).answer(job, "x", anyone, returns(1), 1).final_now);  // verification off
}

TEST(WorkerTrust, ALateAnswerConfirmsTheResultsTakenOrReopensThemAndFinalResultsDecide) {
  WorkerTrust trust = checking();
  Settlement alike = trust.late_answer({"taken", returns(1)}, false, {"late", returns(1)}, false);
  EXPECT_EQ(alike.kind, Settlement::Kind::kStands);
  EXPECT_EQ(alike.passed, (std::vector<WorkerId>{"taken", "late"}));
  EXPECT_EQ(alike.checked_since, "taken");

  Settlement differ = trust.late_answer({"taken", returns(1)}, false, {"late", returns(2)}, false);
  EXPECT_EQ(differ.kind, Settlement::Kind::kReopen);
  ASSERT_EQ(differ.reopened.size(), 2u);
  EXPECT_EQ(differ.reopened[0].worker, "taken");
  EXPECT_EQ(differ.reopened[1].worker, "late");

  Settlement against_final = trust.late_answer({"checked", returns(1)}, true, {"late", returns(2)}, false);
  EXPECT_EQ(against_final.kind, Settlement::Kind::kStands);
  EXPECT_EQ(against_final.wrong, (std::vector<WorkerId>{"late"}));
  EXPECT_FALSE(against_final.checked_since);
}

TEST(WorkerTrust, TheCoordinatorsOwnAnswerDecidesAndAJobIsHandedToItOnce) {
  WorkerTrust trust = checking();
  JobTrust job;
  EXPECT_FALSE(trust.coordinator_must_check(7, job, true, false, 0, 0, 1000));  // no answer held
  job.answers = {{"right", returns(1)}, {"wrong", returns(2)}};
  EXPECT_FALSE(trust.coordinator_must_check(7, job, /*queued=*/true, /*checker_connected=*/true, 0, 0, 1000));
  EXPECT_FALSE(trust.coordinator_must_check(7, job, false, false, /*newest_lease=*/500, 1499, 1000));  // held
  EXPECT_TRUE(trust.coordinator_must_check(7, job, false, false, 500, 1500, 1000));  // held past the lease
  EXPECT_TRUE(trust.coordinator_must_check(7, job, true, false, 0, 0, 1000));        // no one can check it
  EXPECT_EQ(trust.take_coordinator_jobs(), (std::vector<uint64_t>{7}));
  EXPECT_TRUE(trust.take_coordinator_jobs().empty());
  Settlement settled = trust.coordinator_answer(job, returns(1));
  EXPECT_EQ(settled.kind, Settlement::Kind::kTake);
  EXPECT_EQ(settled.credited, kCoordinatorAnswer);
  EXPECT_EQ(settled.passed, (std::vector<WorkerId>{"right"}));
  EXPECT_EQ(settled.wrong, (std::vector<WorkerId>{"wrong"}));
  EXPECT_EQ(settled.why_wrong, "returned results that the coordinator, computing them itself, did not");
  EXPECT_EQ(trust.coordinator_checks(), 1);

  JobTrust other;
  other.answers = job.answers;
  trust.coordinator_must_check(8, other, true, false, 0, 0, 1000);
  trust.end_batch();
  EXPECT_TRUE(trust.take_coordinator_jobs().empty());  // a batch's checks end with it
  EXPECT_TRUE(trust.forget_answers_of(job, "wrong", "wrong"));
  EXPECT_FALSE(trust.forget_answers_of(job, "wrong", "wrong"));
  EXPECT_EQ(job.answers.size(), 1u);
}

}  // namespace
}  // namespace poet
