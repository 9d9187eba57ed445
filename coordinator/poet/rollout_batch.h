#pragma once
// How the loop turns its needs into rollout tasks and reads the results back: one batch collects the tasks of
// many ES steps and evaluations, runs them through the Evaluator in one call, and hands each requester its
// slice. ES steps are 2n tasks (θ ± σε for n perturbation keys, interleaved plus/minus); an evaluation is one
// episode on the environment's own course, or eval_episodes fresh courses when environments are stochastic.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "es/es_settings.h"
#include "evaluator/evaluator.h"
#include "poet.pb.h"
#include "poet/run_state.h"

namespace poet {

using SharedParams = std::shared_ptr<const std::vector<double>>;

inline SharedParams share(std::vector<double> params) {
  return std::make_shared<const std::vector<double>>(std::move(params));
}

// The episode settings every task of a run shares.
struct EpisodeSettings {
  WalkerOptions walker;
  int max_steps = 0;
  bool stochastic = false;
  int eval_episodes = 1;  // 1 unless stochastic
};
EpisodeSettings episode_settings(const pb::RunConfig& config);

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

  // The outcomes of these ES steps, in order. Their gradients (a rebuild of every ε, some 40 ms for 512
  // perturbations) are computed on all of this machine's cores, each by the same serial code, so the numbers do
  // not depend on the core count.
  std::vector<EsOutcome> es_outcomes(std::span<const size_t> handles, const EsSettings& settings) const;
  EsOutcome es_outcome(size_t handle, const EsSettings& settings) const;
  Evaluation evaluation(size_t handle) const;
  size_t size() const { return tasks_.size(); }

 private:
  struct Slot {
    size_t offset = 0;
    size_t count = 0;
    std::vector<uint64_t> keys;  // ES steps: the perturbation keys
    double sigma = 0;
  };
  RolloutTask task(SharedParams theta, const EnvDef& env) const;

  EpisodeSettings settings_;
  std::vector<RolloutTask> tasks_;
  std::vector<Slot> slots_;
  std::vector<RolloutResult> results_;
};

}  // namespace poet
