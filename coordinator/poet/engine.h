#pragma once
// The engine of a run: POET (spec §3) and the paper's controls as modes of one loop over an Evaluator. Pure
// logic: every random number is drawn by address from the run seed, and all rollouts go through the
// evaluator in whole batches, so the same config gives the same state whatever runs the batches.

#include "evaluator/evaluator.h"
#include "poet/iteration_report.h"
#include "poet/run_state.h"

namespace poet {

// The state before iteration 0: one pair on the mode's first environment (flat with seed = run seed mod 10^6
// for POET; the target for ES alone; flat with the target's seed for the direct path), θ from the run's init
// stream, a fresh optimizer. Precondition: validate(config) passed.
RunState initial_state(const pb::RunConfig& config);

// True when the run has nothing left to do: the iteration limit is reached or a control's stopping rule met.
bool run_complete(const RunState& state);

// Runs iteration state.next_iteration (reproduce, optimise, transfer, or the control's steps) and advances
// next_iteration. Throws what the evaluator throws; the state is then unspecified (resume from a checkpoint).
IterationReport run_iteration(RunState& state, Evaluator& evaluator);

}  // namespace poet
