// A run is a function of its config and seed: real rollouts on 1 or 2 threads, straight through or stopped,
// checkpointed and resumed, end in byte-identical checkpoints.

#include <gtest/gtest.h>

#include "evaluator/local_evaluator.h"
#include "poet/checkpoint.h"
#include "poet/engine.h"
#include "rng.h"

namespace poet {
namespace {

// Short real episodes; reproduction and transfer every other iteration with criteria every child passes.
pb::RunConfig small_run() {
  pb::RunConfig c;
  c.set_seed(5);
  c.set_iterations(7);
  c.mutable_es()->set_perturbations(3);
  c.mutable_walker()->set_max_steps(100);
  pb::PoetConfig* p = c.mutable_poet();
  p->set_mutation_interval(2);
  p->set_transfer_interval(2);
  p->set_repro_threshold(-1000);
  p->set_mc_low(-1000);
  p->set_mc_high(1000);
  p->set_max_children(3);
  p->set_max_admitted(1);
  p->set_active_cap(3);
  return c;
}

std::string checkpoint_bytes(const RunState& s) { return to_checkpoint(s).SerializeAsString(); }

uint64_t digest(const std::string& bytes) {
  uint64_t h = 0;
  for (char c : bytes) h = mix64(h ^ static_cast<unsigned char>(c));
  return h;
}

RunState run(const pb::RunConfig& config, int threads) {
  RunState s = initial_state(config);
  LocalEvaluator evaluator(threads);
  while (!run_complete(s)) run_iteration(s, evaluator);
  return s;
}

TEST(Determinism, OneAndTwoThreadsGiveIdenticalCheckpoints) {
  const RunState a = run(small_run(), 1);
  const RunState b = run(small_run(), 2);
  // the run exercised every part of the loop
  EXPECT_GE(a.pairs.size(), 4u);
  EXPECT_GE(a.active_indices().size(), 2u);
  EXPECT_GT(a.counters.transfer_attempts, 0);
  EXPECT_LT(a.active_indices().size(), a.pairs.size());  // someone retired
  const std::string bytes = checkpoint_bytes(a);
  EXPECT_EQ(bytes, checkpoint_bytes(b));
  std::printf("checkpoint digest %016llx\n", static_cast<unsigned long long>(digest(bytes)));
}

TEST(Determinism, ResumingFromACheckpointContinuesExactly) {
  const std::string straight = checkpoint_bytes(run(small_run(), 2));
  for (int stop : {1, 2, 4}) {
    pb::RunConfig first_leg = small_run();
    first_leg.set_iterations(stop);
    RunState s = run(first_leg, 2);

    // through bytes, as a checkpoint file would carry it
    pb::Checkpoint saved;
    ASSERT_TRUE(saved.ParseFromString(checkpoint_bytes(s)));
    saved.mutable_config()->set_iterations(7);  // the resume extends the limit
    Expected<RunState> restored = from_checkpoint(saved);
    ASSERT_TRUE(restored.has_value()) << restored.error();
    LocalEvaluator evaluator(1);
    while (!run_complete(*restored)) run_iteration(*restored, evaluator);
    EXPECT_EQ(checkpoint_bytes(*restored), straight) << "stopped after " << stop;
  }
}

}  // namespace
}  // namespace poet
