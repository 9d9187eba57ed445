#pragma once
// What the steps of one iteration share (internal to the engine): the state, the evaluator, the run's settings,
// and the report being filled.

#include <span>
#include <string_view>

#include "engine/evaluator.h"
#include "engine/iteration_report.h"
#include "engine/phase_observer.h"
#include "engine/rollout_batch.h"
#include "engine/run_state.h"
#include "simulation/es/es_settings.h"

namespace poet {

struct IterationContext {
  RunState& state;
  Evaluator& evaluator;
  IterationReport& report;
  const RunSettings& settings;
  int t = 0;                        // this iteration
  PhaseObserver* phases = nullptr;  // told when each phase begins, if anyone listens

  // The key of the stream for (run seed, purpose, ids): every random number of a run is drawn by address.
  uint64_t key(std::string_view purpose, std::initializer_list<uint64_t> ids) const;
  void event(RunEvent e) { report.events.push_back(std::move(e)); }
  RolloutBatch batch() const { return RolloutBatch(settings.episodes); }
  void phase(IterationPhase p) const {
    if (phases) phases->phase_begins(p);
  }
};

// The context of iteration state.next_iteration, with the state's settings.
IterationContext iteration_context(RunState& state, Evaluator& evaluator, IterationReport& report);

// Records an evaluation of θ on the pair's own environment: latest score, best score and θ, and the first solve
// (finished and score ≥ solved_score), with a "solved" event saying what the evaluation followed.
void record_evaluation(IterationContext& ctx, Pair& pair, const std::vector<double>& theta, const Evaluation& eval,
                       SolvedBy by);

// Throws RunDiverged unless every value is finite: `what` ("θ after the ES step") of pair, at iteration ctx.t.
void require_finite(const IterationContext& ctx, const Pair& pair, std::span<const double> values,
                    std::string_view what);

// A one-step proposal from θ with gradient g: Adam's next update from `optimizer` with learning rate lr, or SGD.
std::vector<double> propose(ProposalKind kind, const std::vector<double>& theta, const std::vector<double>& g,
                            const OptimizerState& optimizer, double lr, const EsSettings& es);

// The steps of an iteration, in the order run_iteration calls them.
void reproduce(IterationContext& ctx);           // POET modes, every mutation_interval iterations
void optimise(IterationContext& ctx);            // every mode: one ES step per active pair, then evaluations
void transfer(IterationContext& ctx);            // POET, every transfer_interval iterations
void advance_curriculum(IterationContext& ctx);  // DIRECT_PATH: stage changes and the stopping rule
void finish_if_solved(IterationContext& ctx);    // ES_ALONE with stop_when_solved: its stopping rule

}  // namespace poet
