#include "simulation/rollout_task.h"

#include <stdexcept>

#include "simulation/es/perturbation.h"
#include "simulation/policy/mlp.h"
#include "simulation/walker/terrain.h"

namespace poet {

RolloutResult run_task(const RolloutTask& task, std::stop_token stop) {
  if (!task.theta) throw std::invalid_argument("rollout task: no policy parameters");
  if (task.max_steps < 1) throw std::invalid_argument("rollout task: max_steps must be ≥ 1");
  const RolloutLimits limits{.max_steps = task.max_steps, .stop = std::move(stop)};
  if (!task.perturbation) return rollout(Mlp(*task.theta), Terrain::generate(task.env), task.walker, limits);

  const Perturbation& p = *task.perturbation;
  if (p.sign != 1 && p.sign != -1) throw std::invalid_argument("rollout task: perturbation sign must be ±1");
  std::vector<double> params(task.theta->size());
  perturb(*task.theta, p.key, p.sign, p.sigma, params);
  return rollout(Mlp(params), Terrain::generate(task.env), task.walker, limits);
}

}  // namespace poet
