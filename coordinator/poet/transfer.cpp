// Step 3 of an iteration (spec §3): every pair tries every other pair's θ (direct) and a one-step proposal from
// it (made with the target's σ, lr and Adam moments). All evaluations use the θs as they stood before the round
// — two batches: direct evaluations with the proposals' ES rollouts, then the proposals' evaluations — and the
// replacements are applied together afterwards.

#include "poet/iteration_context.h"

namespace poet {
namespace {

// One candidate θ for a target pair.
struct Candidate {
  int source = kNone;
  bool proposal = false;
  std::vector<double> theta;
  size_t eval = 0;  // evaluation handle
};

}  // namespace

void transfer(IterationContext& ctx) {
  const int interval = ctx.config.poet().transfer_interval();
  const std::vector<size_t> active = ctx.state.active_indices();
  if (ctx.t % interval != 0 || active.size() < 2) return;
  const auto u = [](auto v) { return static_cast<uint64_t>(v); };

  // round 1: direct evaluations and the proposals' ES steps
  RolloutBatch first = ctx.batch();
  std::vector<std::vector<Candidate>> direct(active.size()), proposals(active.size());
  std::vector<std::vector<size_t>> es_handles(active.size());
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& target = ctx.state.pairs[active[a]];
    for (size_t b : active) {
      const Pair& source = ctx.state.pairs[b];
      if (source.id == target.id) continue;
      const SharedParams theta = share(source.theta);
      const uint64_t eval_key = ctx.key("transfer-eval", {u(ctx.t), u(target.id), u(source.id), 0});
      direct[a].push_back({source.id, false, source.theta, first.add_evaluation(theta, target.env, eval_key)});
      const uint64_t step_key = ctx.key("transfer-noise", {u(ctx.t), u(target.id), u(source.id)});
      es_handles[a].push_back(
          first.add_es_step({theta, target.env, target.optimizer.sigma, step_key}, ctx.es.perturbations));
    }
  }
  first.run(ctx.evaluator, ctx.state.counters, ctx.es);

  // round 2: the proposals' evaluations
  RolloutBatch second = ctx.batch();
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& target = ctx.state.pairs[active[a]];
    const std::vector<EsOutcome> outcomes = first.es_outcomes(es_handles[a], ctx.es);  // one target at a time
    for (size_t s = 0; s < direct[a].size(); ++s) {
      const Candidate& d = direct[a][s];
      const EsOutcome& out = outcomes[s];
      std::vector<double> theta = propose(ctx.config.poet().transfer_proposal(), d.theta, out.gradient,
                                          target.optimizer, target.optimizer.lr, ctx.es);
      require_finite(ctx, target, theta, "the transfer proposal from pair " + std::to_string(d.source));
      const uint64_t eval_key = ctx.key("transfer-eval", {u(ctx.t), u(target.id), u(d.source), 1});
      const size_t handle = second.add_evaluation(share(theta), target.env, eval_key);
      proposals[a].push_back({d.source, true, std::move(theta), handle});
    }
  }
  second.run(ctx.evaluator, ctx.state.counters);

  // the choices: the best transfer, first in order on ties, replaces θ if strictly better than the latest score
  for (size_t a = 0; a < active.size(); ++a) {
    Pair& target = ctx.state.pairs[active[a]];
    const Candidate* best = nullptr;
    Evaluation best_eval;
    for (const auto* list : {&direct[a], &proposals[a]}) {
      for (const Candidate& c : *list) {
        const Evaluation e = (c.proposal ? second : first).evaluation(c.eval);
        if (!best || e.score > best_eval.score) {
          best = &c;
          best_eval = e;
        }
      }
    }
    target.transfer_attempts += 1;
    ctx.state.counters.transfer_attempts += 1;
    if (!best || !(best_eval.score > target.latest_score)) continue;

    const double previous = target.latest_score;
    target.theta = best->theta;
    reset(target.optimizer, ctx.es);
    target.transfers.push_back({ctx.t, best->source, best->proposal, best_eval.score});
    ctx.state.counters.transfer_successes += 1;
    ctx.event("transfer", {{"target", target.id},
                           {"source", best->source},
                           {"proposal", best->proposal},
                           {"score", best_eval.score},
                           {"previous_score", previous}});
    record_evaluation(ctx, target, target.theta, best_eval);
  }
}

}  // namespace poet
