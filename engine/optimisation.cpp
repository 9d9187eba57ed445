// Step 2 of an iteration (spec §3): one ES step for every active pair, all in one batch, then every new θ
// evaluated on its own environment in a second batch.

#include <cmath>

#include "engine/iteration_context.h"

namespace poet {
namespace {

double norm(const std::vector<double>& x) {
  double s = 0;
  for (double v : x) s += v * v;
  return std::sqrt(s);
}

}  // namespace

void optimise(IterationContext& ctx) {
  const std::vector<size_t> active = ctx.state.active_indices();
  const int n = ctx.settings.es.perturbations;

  // every pair's perturbations in one batch
  RolloutBatch steps = ctx.batch();
  std::vector<size_t> handles;
  for (size_t i : active) {
    const Pair& p = ctx.state.pairs[i];
    const uint64_t key = ctx.key("noise", {static_cast<uint64_t>(p.id), static_cast<uint64_t>(ctx.t)});
    handles.push_back(steps.add_es_step({share(p.theta), p.env, p.optimizer.sigma, key}, n));
  }
  ctx.phase(IterationPhase::kEsSteps);
  steps.run(ctx.evaluator, ctx.state.counters, ctx.settings.es);

  // the updates: Adam on the gradient, then the decays (σ was used before its decay)
  std::vector<PairStatsRow> rows;
  RolloutBatch evals = ctx.batch();
  std::vector<size_t> eval_handles;
  const std::vector<EsOutcome> outcomes = steps.es_outcomes(handles, ctx.settings.es);
  for (size_t a = 0; a < active.size(); ++a) {
    Pair& p = ctx.state.pairs[active[a]];
    const EsOutcome& out = outcomes[a];
    PairStatsRow row;
    row.iteration = ctx.t;
    row.pair = p.id;
    row.env = p.env.encoding.name;
    row.sigma = p.optimizer.sigma;
    row.perturbation_mean = out.mean_return;
    row.perturbation_max = out.max_return;
    row.grad_norm = norm(out.gradient);
    require_finite(ctx, p, out.gradient, "the ES gradient");
    adam_step(p.theta, out.gradient, p.optimizer, ctx.settings.es);
    require_finite(ctx, p, p.theta, "θ after the ES step");
    require_finite(ctx, p, p.optimizer.m, "Adam's first moment after the ES step");
    require_finite(ctx, p, p.optimizer.v, "Adam's second moment after the ES step");
    decay(p.optimizer, ctx.settings.es);
    p.es_steps += 1;
    row.lr = p.optimizer.lr;
    row.theta_norm = norm(p.theta);
    rows.push_back(std::move(row));
    const uint64_t key = ctx.key("eval", {static_cast<uint64_t>(p.id), static_cast<uint64_t>(ctx.t)});
    eval_handles.push_back(evals.add_evaluation(share(p.theta), p.env, key));
  }
  ctx.phase(IterationPhase::kEvaluations);
  evals.run(ctx.evaluator, ctx.state.counters);

  for (size_t a = 0; a < active.size(); ++a) {
    Pair& p = ctx.state.pairs[active[a]];
    const Evaluation e = evals.evaluation(eval_handles[a]);
    p.es_env_steps += steps.env_steps(handles[a]) + evals.env_steps(eval_handles[a]);
    record_evaluation(ctx, p, p.theta, e, SolvedBy::kOwnEs);
    PairStatsRow& row = rows[a];
    row.score = e.score;
    row.finished = e.finished;
    row.eval_steps = e.steps;
    row.best_score = p.best_score;
    row.solved = p.solved();
    row.es_steps = p.es_steps;
    row.run_rollouts = ctx.state.counters.rollouts;
    row.run_env_steps = ctx.state.counters.env_steps;
    row.pair_env_steps = p.es_env_steps;
  }
  ctx.report.stats = std::move(rows);
}

}  // namespace poet
