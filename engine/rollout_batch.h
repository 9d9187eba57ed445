#pragma once
// How the loop turns its needs into rollout tasks and reads the results back: one batch collects the tasks of
// many ES steps and evaluations, runs them through the Evaluator in one call, and hands each requester its
// slice. ES steps are 2n tasks (θ ± σε for n perturbation keys, interleaved plus/minus); an evaluation is one
// episode on the environment's own course, or eval_episodes fresh courses when environments are stochastic (of
// the environment's encoding, or with ES alone's domain randomisation of encodings drawn at a level).

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "engine/evaluator.h"
#include "engine/run_state.h"
#include "simulation/es/es_settings.h"

namespace poet {

using SharedParams = std::shared_ptr<const std::vector<double>>;

inline SharedParams share(std::vector<double> params) {
  return std::make_shared<const std::vector<double>>(std::move(params));
}

// One ES step's request: perturbations of θ on env with noise σ; ε keys derive from step_key.
struct EsRequest {
  SharedParams theta;
  EnvDef env;
  double sigma = 0;
  uint64_t step_key = 0;
};

// The result of an ES step's rollouts.
struct EsOutcome {
  std::vector<double> gradient;
  double mean_return = 0;  // over the 2n rollouts
  double max_return = 0;
};

// The score of an evaluation: the mean return over its episodes; finished when every episode finished.
struct Evaluation {
  double score = 0;
  bool finished = false;
  int steps = 0;  // the first episode's steps
};

class RolloutBatch {
 public:
  explicit RolloutBatch(const EpisodeSettings& settings) : settings_(settings) {}

  // Each add returns a handle for reading the results after run().
  size_t add_es_step(const EsRequest& request, int perturbations);
  size_t add_evaluation(SharedParams theta, const EnvDef& env, uint64_t eval_key);

  // Runs every task added so far in one evaluator call (none when there are no tasks); counts rollouts and
  // environment steps. Throws std::runtime_error on a wrong number of results or a non-finite return.
  void run(Evaluator& evaluator, RunCounters& counters);
  // The same, and each ES step's outcome for `es` is computed on background threads as soon as the evaluator
  // reports the step's results final, while the rest of the batch runs; es_outcomes(…, es) then finds it done.
  // The threads are joined before run returns or throws. Throws std::runtime_error when the evaluator returns a
  // return other than the one it reported.
  void run(Evaluator& evaluator, RunCounters& counters, const EsSettings& es);

  // The outcomes of these ES steps, in order: those computed during run(…, settings), the others computed now on
  // all of this machine's cores. Either way each comes from es_outcome on the same results, so the numbers
  // depend neither on the core count nor on when the results arrived.
  std::vector<EsOutcome> es_outcomes(std::span<const size_t> handles, const EsSettings& settings) const;
  // One ES step's outcome, computed now: the gradient rebuilds every ε (some 10 ms for 256 perturbations).
  EsOutcome es_outcome(size_t handle, const EsSettings& settings) const;
  Evaluation evaluation(size_t handle) const;
  // The environment steps of a request's rollouts (an ES step's 2n, an evaluation's episodes).
  int64_t env_steps(size_t handle) const;
  size_t size() const { return tasks_.size(); }

 private:
  struct Slot {
    size_t offset = 0;
    size_t count = 0;
    std::vector<uint64_t> keys;  // ES steps: the perturbation keys
    double sigma = 0;
  };
  // The course of rollout `index` of what `key` is for: env itself, or with stochastic courses a fresh seed (and
  // with domain randomisation a fresh encoding at the level).
  EnvDef course(const EnvDef& env, uint64_t key, uint64_t index) const;
  RolloutTask task(SharedParams theta, const EnvDef& env) const;
  size_t slot_of(size_t task) const;
  std::vector<RolloutResult> evaluate_early(Evaluator& evaluator, const EsSettings& es);
  void accept(std::vector<RolloutResult> results, RunCounters& counters);

  EpisodeSettings settings_;
  std::vector<RolloutTask> tasks_;
  std::vector<Slot> slots_;
  std::vector<RolloutResult> results_;
  std::vector<std::optional<EsOutcome>> early_;  // by slot: ES outcomes computed while the batch ran
  EsSettings early_settings_;                    // the settings they were computed with
};

}  // namespace poet
