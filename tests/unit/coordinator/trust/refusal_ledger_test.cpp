// Tests coordinator/trust/refusal_ledger.cpp: refusing a worker whose unchecked answers became final in an
// earlier batch asks, once, to go back to before the earliest such batch.
#include "coordinator/trust/refusal_ledger.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

TEST(RefusalLedger, RefusingAWorkerWithEarlierUncheckedAnswersAsksOnceToGoBackBeforeTheEarliest) {
  RefusalLedger ledger;
  ledger.note_unchecked("a", 3);
  ledger.note_unchecked("a", 5);  // the first one counts
  ledger.note_unchecked("b", 4);
  EXPECT_EQ(ledger.unchecked_since(), (std::vector<uint64_t>{3, 4}));
  EXPECT_TRUE(ledger.refuse("b", {"worker-b", "wrong"}, 6));
  EXPECT_FALSE(ledger.refuse("b", {"worker-b", "wrong"}, 6));  // once
  EXPECT_TRUE(ledger.refuse("a", {"worker-a", "wrong"}, 6));
  EXPECT_TRUE(ledger.refused("a"));
  ASSERT_EQ(ledger.refusals().size(), 2u);
  EXPECT_EQ(ledger.refusals()[0].name, "worker-b");
  EXPECT_EQ(ledger.refusals()[1].name, "worker-a");
  EXPECT_EQ(ledger.unchecked_since(), (std::vector<uint64_t>{3}));  // the rollback asked for, not yet taken
  EXPECT_EQ(ledger.take_rollback(), 3u);
  EXPECT_EQ(ledger.take_rollback(), std::nullopt);
  EXPECT_EQ(ledger.rollbacks(), 1);
}

TEST(RefusalLedger, AnswersOfTheBatchUnderWayNeedNoGoingBackAndForgottenOnesNone) {
  RefusalLedger ledger;
  ledger.note_unchecked("a", 7);
  ledger.note_unchecked("b", 2);
  ledger.note_unchecked("c", 5);
  ledger.forget_workers([](const WorkerId& id) { return id == "b"; });  // gone
  ledger.forget_batches_from(6);                                        // went back to before batch 6
  EXPECT_EQ(ledger.unchecked_since(), (std::vector<uint64_t>{5}));
  ledger.note_unchecked("d", 7);
  EXPECT_TRUE(ledger.refuse("d", {"worker-d", "wrong"}, 7));  // its answers are of batch 7, the one under way
  EXPECT_EQ(ledger.take_rollback(), std::nullopt);
}

}  // namespace
}  // namespace poet
