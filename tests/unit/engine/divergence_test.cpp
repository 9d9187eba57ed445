// Divergence is caught at the step where it happens: the engine throws RunDiverged naming the pair, the
// iteration and what stopped being finite, and saying that a resume would repeat it.

#include <gtest/gtest.h>

#include "engine_test_support.h"
#include "scripted_evaluator.h"

namespace poet::testing {
namespace {

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

TEST(Divergence, AnOverflowingMomentStopsTheRunAtItsStep) {
  pb::RunConfig c = tiny_config();
  c.mutable_es()->set_sigma_decay(1e-300);  // σ = 1e-301 after the first step, so g/σ overflows Adam's v next
  c.mutable_es()->set_sigma_floor(0);
  RunState s = initial_state(run_settings(c));
  ScriptedEvaluator ev([](int, size_t i, const RolloutTask&) { return scored(static_cast<double>(i)); });
  run_iteration(s, ev);  // iteration 0 uses σ = 0.1
  try {
    run_iteration(s, ev);
    FAIL() << "iteration 1 did not diverge";
  } catch (const RunDiverged& e) {
    const std::string what = e.what();
    EXPECT_TRUE(contains(what, "the run diverged at iteration 1: pair 0")) << what;
    EXPECT_TRUE(contains(what, "Adam's second moment after the ES step")) << what;
    EXPECT_TRUE(contains(what, "resuming from the last checkpoint will repeat this")) << what;
  }
}

TEST(Divergence, FiniteRunsAreNotFlagged) {
  pb::RunConfig c = tiny_config();
  RunState s = initial_state(run_settings(c));
  ScriptedEvaluator ev([](int, size_t i, const RolloutTask&) { return scored(static_cast<double>(i % 7)); });
  for (int i = 0; i < 5; ++i) EXPECT_NO_THROW(run_iteration(s, ev));
}

}  // namespace
}  // namespace poet::testing
