// A run is a function of its config and seed: real rollouts on 1 or 2 threads, straight through or stopped,
// checkpointed and resumed, end in byte-identical checkpoints — for obstacle courses, CPPN terrain, PATA-EC novelty
// and the three together (Enhanced POET).

#include <gtest/gtest.h>

#include "coordinator/evaluator/local_evaluator.h"
#include "engine/engine.h"
#include "engine_test_support.h"
#include "run_directory/files/checkpoint.h"

namespace poet {
namespace {

// The runs checked: their configs by name.
pb::RunConfig run_config(std::string_view name) {
  pb::RunConfig c = testing::small_real_run();
  if (name == "cppn") c = testing::small_cppn_run();
  if (name == "pata_ec") c = testing::small_pata_ec_run();
  if (name == "enhanced") {
    c = testing::small_cppn_run();
    c.mutable_poet()->set_child_ranking(pb::NOVELTY);
    c.mutable_poet()->set_novelty(pb::PATA_EC);
    c.mutable_poet()->set_transfer_test(pb::THRESHOLD_TRANSFER_TEST);
  }
  return c;
}

class Determinism : public ::testing::TestWithParam<std::string> {
 protected:
  pb::RunConfig small_run() const { return run_config(GetParam()); }
  std::string checkpoint_bytes(const RunState& s) const { return to_checkpoint(small_run(), s).SerializeAsString(); }
};

RunState run(const pb::RunConfig& config, int threads) {
  RunState s = initial_state(run_settings(config));
  LocalEvaluator evaluator(threads);
  while (!run_complete(s)) run_iteration(s, evaluator);
  return s;
}

TEST_P(Determinism, OneAndTwoThreadsGiveIdenticalCheckpoints) {
  const RunState a = run(small_run(), 1);
  const RunState b = run(small_run(), 2);
  // the run exercised every part of the loop
  EXPECT_GE(a.pairs.size(), 4u);
  EXPECT_GE(a.active_indices().size(), 2u);
  EXPECT_GT(a.counters.transfer_attempts, 0);
  EXPECT_LT(a.active_indices().size(), a.pairs.size());  // someone retired
  // the numbers themselves are pinned by golden_test.cpp
  EXPECT_EQ(checkpoint_bytes(a), checkpoint_bytes(b));
}

TEST_P(Determinism, ResumingFromACheckpointContinuesExactly) {
  const std::string straight = checkpoint_bytes(run(small_run(), 2));
  for (int stop : {1, 2, 4}) {
    pb::RunConfig first_leg = small_run();
    first_leg.set_iterations(stop);
    RunState s = run(first_leg, 2);

    // through bytes, as a checkpoint file would carry it
    pb::Checkpoint saved;
    ASSERT_TRUE(saved.ParseFromString(checkpoint_bytes(s)));
    saved.mutable_config()->set_iterations(small_run().iterations());  // the resume extends the limit
    Expected<RunState> restored = from_checkpoint(saved);
    ASSERT_TRUE(restored.has_value()) << restored.error();
    LocalEvaluator evaluator(1);
    while (!run_complete(*restored)) run_iteration(*restored, evaluator);
    EXPECT_EQ(checkpoint_bytes(*restored), straight) << "stopped after " << stop;
  }
}

INSTANTIATE_TEST_SUITE_P(Runs, Determinism, ::testing::Values("obstacles", "cppn", "pata_ec", "enhanced"),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace poet
