// A run is a function of its config and seed: real rollouts on 1 or 2 threads, straight through or stopped,
// checkpointed and resumed, end in byte-identical checkpoints, with either novelty measure.

#include <gtest/gtest.h>

#include "engine_test_support.h"
#include "evaluator/local_evaluator.h"
#include "poet/engine.h"
#include "run/checkpoint.h"

namespace poet {
namespace {

std::string checkpoint_bytes(const pb::RunConfig& config, const RunState& s) {
  return to_checkpoint(config, s).SerializeAsString();
}

RunState run(const pb::RunConfig& config, int threads) {
  RunState s = initial_state(run_settings(config));
  LocalEvaluator evaluator(threads);
  while (!run_complete(s)) run_iteration(s, evaluator);
  return s;
}

void expect_one_and_two_threads_agree(const pb::RunConfig& config) {
  const RunState a = run(config, 1);
  const RunState b = run(config, 2);
  // the run exercised every part of the loop
  EXPECT_GE(a.pairs.size(), 4u);
  EXPECT_GE(a.active_indices().size(), 2u);
  EXPECT_GT(a.counters.transfer_attempts, 0);
  EXPECT_LT(a.active_indices().size(), a.pairs.size());  // someone retired
  // the numbers themselves are pinned by golden_test.cpp
  EXPECT_EQ(checkpoint_bytes(config, a), checkpoint_bytes(config, b));
}

void expect_resume_continues_exactly(const pb::RunConfig& config) {
  const std::string straight = checkpoint_bytes(config, run(config, 2));
  for (int stop : {1, 2, 4}) {
    pb::RunConfig first_leg = config;
    first_leg.set_iterations(stop);
    RunState s = run(first_leg, 2);

    // through bytes, as a checkpoint file would carry it
    pb::Checkpoint saved;
    ASSERT_TRUE(saved.ParseFromString(checkpoint_bytes(config, s)));
    saved.mutable_config()->set_iterations(config.iterations());  // the resume extends the limit
    Expected<RunState> restored = from_checkpoint(saved);
    ASSERT_TRUE(restored.has_value()) << restored.error();
    LocalEvaluator evaluator(1);
    while (!run_complete(*restored)) run_iteration(*restored, evaluator);
    EXPECT_EQ(checkpoint_bytes(config, *restored), straight) << "stopped after " << stop;
  }
}

TEST(Determinism, OneAndTwoThreadsGiveIdenticalCheckpoints) {
  expect_one_and_two_threads_agree(testing::small_real_run());
}

TEST(Determinism, ResumingFromACheckpointContinuesExactly) {
  expect_resume_continues_exactly(testing::small_real_run());
}

// PATA-EC's characterisations are batches of their own, with keys of their own.
TEST(Determinism, WithPataEcOneAndTwoThreadsGiveIdenticalCheckpoints) {
  expect_one_and_two_threads_agree(testing::small_pata_ec_run());
}

TEST(Determinism, WithPataEcResumingFromACheckpointContinuesExactly) {
  expect_resume_continues_exactly(testing::small_pata_ec_run());
}

}  // namespace
}  // namespace poet
