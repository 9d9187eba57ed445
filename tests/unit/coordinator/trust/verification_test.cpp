// Tests coordinator/trust/verification.cpp: which jobs are chosen for a check, whose answers need one, and what
// two or three answers to a job say.
#include "coordinator/trust/verification.h"

#include <gtest/gtest.h>

#include "answers.h"

namespace poet {
namespace {

using testing::returns;

Standing worker(bool local, int64_t checks_passed) {
  Standing view;
  view.local = local;
  view.checks_passed = checks_passed;
  return view;
}

TEST(Verification, TheSecretChoosesAboutTheFractionOfJobsAndOnlyItKnowsWhich) {
  Verification a(0.25, 1234, 5), b(0.25, 99, 5), off(0, 1234, 5);
  int chosen = 0, differ = 0;
  for (size_t job = 0; job < 4000; ++job) {
    chosen += a.chosen(1, job, job + 1);
    differ += a.chosen(1, job, job + 1) != b.chosen(1, job, job + 1);
    EXPECT_FALSE(off.chosen(1, job, job + 1));
  }
  EXPECT_NEAR(chosen / 4000.0, 0.25, 0.03);
  EXPECT_GT(differ, 1000);                                                        // another secret, other jobs
  EXPECT_EQ(a.chosen(7, 10, 20), Verification(0.25, 1234, 5).chosen(7, 10, 20));  // a function of its inputs
}

TEST(Verification, ANewWorkersAnswersAreCheckedUntilItsProbationEndsAndAnAnswerHeldAgainstTheNextWhoeverGivesIt) {
  Verification v(0.1, 1, 2);
  EXPECT_TRUE(v.needs_check(false, worker(false, 0), false));  // on probation
  EXPECT_TRUE(v.needs_check(false, worker(false, 1), false));
  EXPECT_FALSE(v.needs_check(false, worker(false, 2), false));  // probation over, job not chosen
  EXPECT_TRUE(v.needs_check(true, worker(false, 2), false));    // chosen
  EXPECT_FALSE(v.needs_check(true, worker(true, 0), false));    // a local worker's answer stands alone
  EXPECT_TRUE(v.needs_check(true, worker(true, 0), true));      // but settles one held
  // an answer held (a newcomer's) is compared with the next, even a proven worker's to a job not chosen
  EXPECT_TRUE(v.needs_check(false, worker(false, 2), true));
  EXPECT_TRUE(v.needs_check(false, worker(true, 0), true));
  EXPECT_FALSE(v.final_unchecked(worker(false, 9)));
  EXPECT_TRUE(v.final_unchecked(worker(true, 0)));
  EXPECT_TRUE(Verification(0, 1, 2).final_unchecked(worker(false, 0)));
  EXPECT_FALSE(Verification(0, 1, 2).needs_check(false, worker(false, 0), false));
}

TEST(Verification, TwoAnswersAlikeAreTakenTwoThatDifferWaitForAThirdWhichDecidesAndThreeGoToTheCoordinator) {
  Verification v(0.1, 1, 2);
  std::vector<Answer> held;
  EXPECT_EQ(v.judge(held, {"a", returns(1.0)}, false).kind, Verdict::Kind::kHold);
  held.push_back({"a", returns(1.0)});
  const Verdict alike = v.judge(held, {"b", returns(1.0)}, false);
  EXPECT_EQ(alike.kind, Verdict::Kind::kTake);
  EXPECT_EQ(alike.credited, "a");
  EXPECT_EQ(alike.passed, (std::vector<WorkerId>{"a", "b"}));
  EXPECT_TRUE(alike.wrong.empty());
  EXPECT_EQ(v.verified(), 1);

  EXPECT_EQ(v.judge(held, {"b", returns(2.0)}, false).kind, Verdict::Kind::kHold);  // a third decides
  held.push_back({"b", returns(2.0)});
  const Verdict third = v.judge(held, {"c", returns(2.0)}, false);
  EXPECT_EQ(third.kind, Verdict::Kind::kTake);
  EXPECT_EQ(third.credited, "c");
  EXPECT_EQ(third.passed, (std::vector<WorkerId>{"b", "c"}));
  EXPECT_EQ(third.wrong, (std::vector<WorkerId>{"a"}));
  EXPECT_EQ(v.judge(held, {"c", returns(3.0)}, false).kind, Verdict::Kind::kCoordinator);  // three, none confirmed
  EXPECT_EQ(v.verified(), 2);
}

TEST(Verification, ALocalWorkerThatDiffersDecidesAtOnce) {
  Verification v(0.1, 1, 2);
  const Verdict verdict = v.judge({{"a", returns(1.0)}}, {"local", returns(1.5)}, true);
  EXPECT_EQ(verdict.kind, Verdict::Kind::kTake);
  EXPECT_EQ(verdict.credited, "local");
  EXPECT_EQ(verdict.wrong, (std::vector<WorkerId>{"a"}));
  EXPECT_TRUE(verdict.passed.empty());
  EXPECT_EQ(v.verified(), 0);
}

// Rule 1: connections that share a CURVE key are one witness, whatever their routing ids.
TEST(Verification, AnswersOfOneWitnessNeitherConfirmNorRefuteEachOther) {
  Verification v(0.1, 1, 2);
  const std::vector<Answer> held = {{"a", returns(1.0), "key-k"}};
  for (const double total : {1.0, 2.0}) {
    const Verdict twin = v.judge(held, {"b", returns(total), "key-k"}, false);
    EXPECT_EQ(twin.kind, Verdict::Kind::kHold);
    EXPECT_FALSE(twin.keep);  // not held: it is no second witness
  }
  EXPECT_EQ(v.judge(held, {"c", returns(1.0), "key-j"}, false).kind, Verdict::Kind::kTake);
  EXPECT_EQ(v.verified(), 1);
  EXPECT_EQ((Answer{"a", {}, ""}.vouched_by()), "a");  // without CURVE, its connection
}

// Rule 2: two answers alike confirm each other only when not both were given on probation.
TEST(Verification, AnAnswerOnProbationNeverConfirmsAnotherOnProbation) {
  Verification v(0.1, 1, 2);
  std::vector<Answer> held = {{"sybil1", returns(9.0), "", true}};
  const Verdict second = v.judge(held, {"sybil2", returns(9.0), "", true}, false);
  EXPECT_EQ(second.kind, Verdict::Kind::kHold);
  EXPECT_TRUE(second.keep);
  held.push_back({"sybil2", returns(9.0), "", true});
  EXPECT_TRUE(Verification::needs_witness_past_probation(held));
  // an honest worker past probation that differs from both: nothing confirmed among three, the coordinator decides
  EXPECT_EQ(v.judge(held, {"honest", returns(1.0)}, false).kind, Verdict::Kind::kCoordinator);
  const CoordinatorVerdict settled = v.settle({held[0], held[1], {"honest", returns(1.0)}}, returns(1.0));
  EXPECT_EQ(settled.wrong, (std::vector<WorkerId>{"sybil1", "sybil2"}));
  EXPECT_EQ(settled.passed, (std::vector<WorkerId>{"honest"}));
  // one past probation that agrees confirms them
  const Verdict confirmed = v.judge(held, {"proven", returns(9.0)}, false);
  EXPECT_EQ(confirmed.kind, Verdict::Kind::kTake);
  EXPECT_EQ(confirmed.passed, (std::vector<WorkerId>{"sybil1", "sybil2", "proven"}));
}

// Rule 3: an answer on probation never refutes a proven worker's; a witness past probation decides the dispute.
TEST(Verification, AnAnswerOnProbationNeverRefutesAndNeverDecidesADispute) {
  Verification v(0.1, 1, 2);
  std::vector<Answer> held = {{"proven", returns(1.0)}};
  const Verdict dispute = v.judge(held, {"newcomer", returns(2.0), "", true}, false);
  EXPECT_EQ(dispute.kind, Verdict::Kind::kHold);  // no one refuted
  EXPECT_TRUE(dispute.wrong.empty());
  held.push_back({"newcomer", returns(2.0), "", true});
  EXPECT_TRUE(Verification::needs_witness_past_probation(held));
  // another newcomer siding with the first decides nothing: three held, the coordinator decides
  EXPECT_EQ(v.judge(held, {"newcomer2", returns(2.0), "", true}, false).kind, Verdict::Kind::kCoordinator);
  // a witness past probation decides, either way
  const Verdict for_proven = v.judge(held, {"decider", returns(1.0)}, false);
  EXPECT_EQ(for_proven.kind, Verdict::Kind::kTake);
  EXPECT_EQ(for_proven.wrong, (std::vector<WorkerId>{"newcomer"}));
  const Verdict for_newcomer = v.judge(held, {"decider", returns(2.0)}, false);
  EXPECT_EQ(for_newcomer.kind, Verdict::Kind::kTake);
  EXPECT_EQ(for_newcomer.credited, "decider");
  EXPECT_EQ(for_newcomer.wrong, (std::vector<WorkerId>{"proven"}));
  EXPECT_FALSE(Verification::needs_witness_past_probation({{"proven", returns(1.0)}}));
}

TEST(Verification, ResultsDifferingInOneBitOrOneStepDiffer) {
  std::vector<RolloutResult> a = returns(1.0), b = returns(1.0);
  EXPECT_TRUE(same_results(a, b));
  b[1].total_reward = std::nextafter(1.0, 2.0);
  EXPECT_FALSE(same_results(a, b));
  b = returns(1.0);
  b[0].steps += 1;
  EXPECT_FALSE(same_results(a, b));
  b = returns(1.0);
  b.pop_back();
  EXPECT_FALSE(same_results(a, b));
}

TEST(Verification, TheCoordinatorsOwnResultsSayWhoWasRightAndWhoWrong) {
  Verification v(0.1, 1, 2);
  const CoordinatorVerdict verdict = v.settle({{"a", returns(1.0)}, {"b", returns(2.0)}}, returns(2.0));
  EXPECT_EQ(verdict.passed, (std::vector<WorkerId>{"b"}));
  EXPECT_EQ(verdict.wrong, (std::vector<WorkerId>{"a"}));
  EXPECT_EQ(v.coordinator_checks(), 1);
  EXPECT_EQ(v.verified(), 1);
}

}  // namespace
}  // namespace poet
