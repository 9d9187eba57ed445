// Step 3 of an iteration (spec §3): every pair tries every other pair's θ on its environment. All evaluations use
// the θs as they stood before the round, and the replacements are applied together afterwards.
//   full test (the paper's): each source directly and as a one-step proposal (made with the target's σ, lr and
//     Adam moments) — two batches: direct evaluations with the proposals' ES rollouts, then the proposals'
//     evaluations; the best of all replaces θ if strictly better than the target's latest score.
//   threshold test (Enhanced POET's): direct evaluations first; only a source that beats the target's threshold
//     (the best of its last five evaluation scores) gets the proposal step — two more batches — and the best
//     proposal that beats the threshold too replaces θ.
//   confirm_transfers (stochastic courses only): a third batch runs each target's choice and its own θ on the same
//     fresh courses, and the choice replaces θ only if it scores above θ there.

#include <algorithm>
#include <optional>

#include "engine/iteration_context.h"

namespace poet {
namespace {

// One candidate θ for a target pair.
struct Candidate {
  int source = kNone;
  bool proposal = false;
  std::vector<double> theta;
  size_t eval = 0;  // evaluation handle
};

double threshold_of(const Pair& target) {
  if (target.recent_scores.empty()) return target.latest_score;
  return *std::max_element(target.recent_scores.begin(), target.recent_scores.end());
}

}  // namespace

void transfer(IterationContext& ctx) {
  const int interval = ctx.settings.poet.transfer_interval;
  const std::vector<size_t> active = ctx.state.active_indices();
  if (ctx.t % interval != 0 || active.size() < 2) return;
  ctx.phase(IterationPhase::kTransfer);
  const bool full = ctx.settings.poet.transfer_test == TransferTest::kFull;
  const auto u = [](auto v) { return static_cast<uint64_t>(v); };
  const auto step_of = [&](RolloutBatch& batch, const Pair& target, const Candidate& source) {
    const uint64_t step_key = ctx.key("transfer-noise", {u(ctx.t), u(target.id), u(source.source)});
    return batch.add_es_step({share(source.theta), target.env, target.optimizer.sigma, step_key},
                             ctx.settings.es.perturbations);
  };

  const int64_t rollouts_before = ctx.state.counters.rollouts;

  // direct evaluations (with the full test, the proposals' ES rollouts in the same batch)
  RolloutBatch first = ctx.batch();
  std::vector<std::vector<Candidate>> direct(active.size()), proposals(active.size());
  std::vector<std::vector<size_t>> es_handles(active.size());
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& target = ctx.state.pairs[active[a]];
    for (size_t b : active) {
      const Pair& source = ctx.state.pairs[b];
      if (source.id == target.id) continue;
      const uint64_t eval_key = ctx.key("transfer-eval", {u(ctx.t), u(target.id), u(source.id), 0});
      direct[a].push_back(
          {source.id, false, source.theta, first.add_evaluation(share(source.theta), target.env, eval_key)});
      if (full) es_handles[a].push_back(step_of(first, target, direct[a].back()));
    }
  }
  first.run(ctx.evaluator, ctx.state.counters, ctx.settings.es);

  // the threshold test: the proposals' ES rollouts, only for the sources that passed it
  std::vector<std::vector<const Candidate*>> stepped(active.size());
  RolloutBatch screened = ctx.batch();
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& target = ctx.state.pairs[active[a]];
    for (const Candidate& d : direct[a]) {
      if (!full && !(first.evaluation(d.eval).score > threshold_of(target))) continue;
      stepped[a].push_back(&d);
      if (!full) es_handles[a].push_back(step_of(screened, target, d));
    }
  }
  if (!full) screened.run(ctx.evaluator, ctx.state.counters, ctx.settings.es);
  const RolloutBatch& stepped_batch = full ? first : screened;

  // the proposals' evaluations
  RolloutBatch second = ctx.batch();
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& target = ctx.state.pairs[active[a]];
    const std::vector<EsOutcome> outcomes =
        stepped_batch.es_outcomes(es_handles[a], ctx.settings.es);  // one target at a time
    for (size_t s = 0; s < stepped[a].size(); ++s) {
      const Candidate& d = *stepped[a][s];
      std::vector<double> theta = propose(ctx.settings.poet.transfer_proposal, d.theta, outcomes[s].gradient,
                                          target.optimizer, target.optimizer.lr, ctx.settings.es);
      require_finite(ctx, target, theta, "the transfer proposal from pair " + std::to_string(d.source));
      const uint64_t eval_key = ctx.key("transfer-eval", {u(ctx.t), u(target.id), u(d.source), 1});
      const size_t handle = second.add_evaluation(share(theta), target.env, eval_key);
      proposals[a].push_back({d.source, true, std::move(theta), handle});
    }
  }
  second.run(ctx.evaluator, ctx.state.counters);

  size_t proposal_count = 0;
  for (const auto& list : proposals) proposal_count += list.size();
  const int64_t successes_before = ctx.state.counters.transfer_successes;

  // the choices: the best transfer, first in order on ties (direct by source order, then proposals), replaces θ
  // if strictly better than the latest score (full test) or than the threshold, as a proposal (threshold test)
  std::vector<const Candidate*> chosen(active.size(), nullptr);
  std::vector<Evaluation> chosen_eval(active.size());
  for (size_t a = 0; a < active.size(); ++a) {
    Pair& target = ctx.state.pairs[active[a]];
    const Candidate* best = nullptr;
    Evaluation best_eval;
    for (const auto* list : {&direct[a], &proposals[a]}) {
      if (!full && list == &direct[a]) continue;
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
    const double bar = full ? target.latest_score : threshold_of(target);
    if (!best || !(best_eval.score > bar)) continue;
    chosen[a] = best;
    chosen_eval[a] = best_eval;
  }

  // with confirm_transfers (stochastic courses), each choice and the target's θ run on the same fresh courses,
  // and the choice stands only if it scores above θ there; its score is then that one, from courses that did
  // not choose it
  std::optional<int64_t> unconfirmed;
  if (ctx.settings.poet.confirm_transfers) {
    unconfirmed = 0;
    RolloutBatch confirm = ctx.batch();
    std::vector<std::pair<size_t, size_t>> handles(active.size());
    for (size_t a = 0; a < active.size(); ++a) {
      if (!chosen[a]) continue;
      const Pair& target = ctx.state.pairs[active[a]];
      const uint64_t key = ctx.key("transfer-confirm", {u(ctx.t), u(target.id)});
      handles[a] = {confirm.add_evaluation(share(chosen[a]->theta), target.env, key),
                    confirm.add_evaluation(share(target.theta), target.env, key)};
    }
    confirm.run(ctx.evaluator, ctx.state.counters);
    for (size_t a = 0; a < active.size(); ++a) {
      if (!chosen[a]) continue;
      const Evaluation candidate = confirm.evaluation(handles[a].first);
      if (candidate.score > confirm.evaluation(handles[a].second).score) {
        chosen_eval[a] = candidate;
      } else {
        chosen[a] = nullptr;
        *unconfirmed += 1;
      }
    }
  }

  for (size_t a = 0; a < active.size(); ++a) {
    if (!chosen[a]) continue;
    Pair& target = ctx.state.pairs[active[a]];
    const Candidate& best = *chosen[a];
    const double previous = target.latest_score;
    target.theta = best.theta;
    reset(target.optimizer, ctx.settings.es);
    target.transfers.push_back({ctx.t, best.source, best.proposal, chosen_eval[a].score});
    ctx.state.counters.transfer_successes += 1;
    ctx.event(TransferEvent{target.id, best.source, best.proposal, chosen_eval[a].score, previous});
    record_evaluation(ctx, target, target.theta, chosen_eval[a]);
  }
  // what the round cost: with the threshold test, the proposals it paid for out of the N(N−1) of the full test
  ctx.event(TransferRoundEvent{full, active.size(), active.size() * (active.size() - 1), proposal_count,
                               ctx.state.counters.transfer_successes - successes_before,
                               ctx.state.counters.rollouts - rollouts_before, unconfirmed});
}

}  // namespace poet
