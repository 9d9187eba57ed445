// Tests run_directory/files/checkpoint_anchors.cpp: which checkpoints are kept for going back, and which one a rollback
// returns to.

#include "run_directory/files/checkpoint_anchors.h"

#include <gtest/gtest.h>

#include <vector>

namespace poet {
namespace {

// Saves at iterations 0, 2, 4, 6 after batches 0, 10, 20, 30 had started.
CheckpointAnchors four_saves() {
  CheckpointAnchors anchors;
  for (int i = 0; i < 4; ++i)
    anchors.add({static_cast<uint64_t>(10 * i), 2 * i, "checkpoint at iteration " + std::to_string(2 * i)});
  return anchors;
}

TEST(CheckpointAnchors, GoesBackToTheNewestSavedBeforeTheFirstBadBatchStarted) {
  const CheckpointAnchors anchors = four_saves();
  ASSERT_NE(anchors.before(25), nullptr);
  EXPECT_EQ(anchors.before(25)->next_iteration, 4);  // saved after batch 20: batch 25 came later
  EXPECT_EQ(anchors.before(21)->next_iteration, 4);
  EXPECT_EQ(anchors.before(20)->next_iteration, 2);  // batch 20 itself had started by the save at 4
  EXPECT_EQ(anchors.before(1)->next_iteration, 0);
  EXPECT_EQ(anchors.before(0), nullptr);  // nothing precedes the first batch
}

TEST(CheckpointAnchors, KeepsTheNewestAndThoseAWorkerThatMayBeFoundWrongNeeds) {
  CheckpointAnchors anchors = four_saves();
  const std::vector<uint64_t> needed = {15, 16};  // two workers' first unchecked answers, both after the save at 2
  anchors.prune(needed);
  EXPECT_EQ(anchors.size(), 2u);
  EXPECT_EQ(anchors.before(15)->next_iteration, 2);
  EXPECT_EQ(anchors.before(100)->next_iteration, 6);
  anchors.prune({});
  EXPECT_EQ(anchors.size(), 1u);
  EXPECT_EQ(anchors.before(100)->bytes, "checkpoint at iteration 6");
}

TEST(CheckpointAnchors, GoingBackDropsWhatWasSavedAfter) {
  CheckpointAnchors anchors = four_saves();
  const CheckpointAnchor back = *anchors.before(15);
  anchors.keep_until(back);
  EXPECT_EQ(anchors.size(), 2u);
  EXPECT_EQ(anchors.before(100)->next_iteration, 2);  // the newest is now the one gone back to
}

}  // namespace
}  // namespace poet
