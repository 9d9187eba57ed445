// run_iteration's phases (poet/phase_observer.h): announced in order, only those the iteration runs, and the same
// with or without an observer (it changes no number).

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "coordinator/evaluator/local_evaluator.h"
#include "engine_test_support.h"
#include "run_directory/files/checkpoint.h"
#include "scripted_evaluator.h"

namespace poet::testing {
namespace {

struct PhaseLog : PhaseObserver {
  std::vector<int> seen;  // phases as numbers, -1 for the iteration's end
  void phase_begins(IterationPhase phase) override { seen.push_back(static_cast<int>(phase)); }
  void iteration_ends() override { seen.push_back(-1); }
};

constexpr int kReproduction = static_cast<int>(IterationPhase::kReproduction);
constexpr int kEsSteps = static_cast<int>(IterationPhase::kEsSteps);
constexpr int kEvaluations = static_cast<int>(IterationPhase::kEvaluations);
constexpr int kTransfer = static_cast<int>(IterationPhase::kTransfer);

TEST(EnginePhases, AnnouncedInOrderOnlyWhenTheyRun) {
  pb::RunConfig c = tiny_config();
  c.mutable_poet()->set_transfer_interval(2);
  c.mutable_poet()->set_max_admitted(1);
  RunState s = state_at(c, 4, 250);
  ScriptedEvaluator ev([](int, size_t, const RolloutTask& t) { return scored(t.perturbation ? 0 : 100); });
  PhaseLog log;
  run_iteration(s, ev, &log);  // 4: reproduction and transfer (a child was admitted: two pairs)
  run_iteration(s, ev, &log);  // 5: ES steps and evaluations only
  EXPECT_EQ(log.seen,
            (std::vector<int>{kReproduction, kEsSteps, kEvaluations, kTransfer, -1, kEsSteps, kEvaluations, -1}));
}

TEST(EnginePhases, AnObserverChangesNoNumber) {
  pb::RunConfig c = small_real_run();
  RunState watched = initial_state(run_settings(c));
  RunState alone = initial_state(run_settings(c));
  LocalEvaluator evaluator(2);
  PhaseLog log;
  for (int i = 0; i < 4; ++i) {
    run_iteration(watched, evaluator, &log);
    run_iteration(alone, evaluator);
  }
  EXPECT_EQ(to_checkpoint(c, watched).SerializeAsString(), to_checkpoint(c, alone).SerializeAsString());
  EXPECT_EQ(std::count(log.seen.begin(), log.seen.end(), -1), 4);
}

}  // namespace
}  // namespace poet::testing
