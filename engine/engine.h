#pragma once
// The engine of a run: POET (spec §3) and the paper's controls as modes of one loop over an Evaluator. Pure
// logic: every random number is drawn by address from the run seed, and all rollouts go through the
// evaluator in whole batches, so the same config gives the same state whatever runs the batches.

#include <optional>
#include <stdexcept>
#include <vector>

#include "engine/evaluator.h"
#include "engine/iteration_report.h"
#include "engine/phase_observer.h"
#include "engine/run_state.h"

namespace poet {

// Thrown by run_iteration at the step where θ, an ES gradient, a proposal or Adam's moments stop being finite.
// A run is a function of its config, so resuming from the last checkpoint repeats the divergence: the message
// says what diverged, where, and that the config must change.
class RunDiverged : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The state before iteration 0: one pair on the mode's first environment (flat with seed = run seed mod 10^6
// for POET; the target for ES alone; flat with the target's seed for the direct path), θ from the run's init
// stream or `start_theta` (a walker that already walks, --start-from), a fresh optimizer. Preconditions:
// settings made from a config that validate() accepts; start_theta, when given, holds kParamCount finite values.
RunState initial_state(const RunSettings& settings, std::optional<std::vector<double>> start_theta = std::nullopt);

// True when the run has nothing left to do: the iteration limit or the environment-step budget is reached, or a
// control's stopping rule met.
bool run_complete(const RunState& state);
// True when the run has an environment-step budget and its environment steps have reached it.
bool budget_reached(const RunState& state);

// Runs iteration state.next_iteration (reproduce, optimise, transfer, or the control's steps) and advances
// next_iteration. Throws RunDiverged, or what the evaluator throws (EvaluationStopped after a stop request); the
// state is then unspecified, and the run continues from its last checkpoint. `phases`, when given, is told as each
// phase begins and when the iteration ends (the same calls with any evaluator).
IterationReport run_iteration(RunState& state, Evaluator& evaluator, PhaseObserver* phases = nullptr);

}  // namespace poet
