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

const auto u = [](auto v) { return static_cast<uint64_t>(v); };

// One candidate θ for a target pair, and once run, its evaluation.
struct Candidate {
  int source = kNone;
  bool proposal = false;
  std::vector<double> theta;
  size_t eval = 0;  // evaluation handle in its batch
  Evaluation evaluation;
};

// What a transfer test leaves for each active target: the candidates that compete (direct ones in source order,
// then proposals) and the bar the best must beat strictly.
struct Contest {
  std::vector<Candidate> entries;
  double bar = 0;
};

struct Round {
  std::vector<Contest> contests;  // by position in `active`
  size_t proposals = 0;           // proposal steps paid for
};

double threshold_of(const Pair& target) {
  if (target.recent_scores.empty()) return target.latest_score;
  return *std::max_element(target.recent_scores.begin(), target.recent_scores.end());
}

// Every other active pair's θ on each target's environment, added to `batch` (in source order).
std::vector<std::vector<Candidate>> add_direct(IterationContext& ctx, const std::vector<size_t>& active,
                                               RolloutBatch& batch) {
  std::vector<std::vector<Candidate>> direct(active.size());
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& target = ctx.state.pairs[active[a]];
    for (size_t b : active) {
      const Pair& source = ctx.state.pairs[b];
      if (source.id == target.id) continue;
      const uint64_t eval_key = ctx.key("transfer-eval", {u(ctx.t), u(target.id), u(source.id), 0});
      direct[a].push_back(
          {source.id, false, source.theta, batch.add_evaluation(share(source.theta), target.env, eval_key), {}});
    }
  }
  return direct;
}

// The ES rollouts of the one-step proposal from `source` on the target (the target's σ), added to `batch`.
size_t add_step(IterationContext& ctx, RolloutBatch& batch, const Pair& target, const Candidate& source) {
  const uint64_t step_key = ctx.key("transfer-noise", {u(ctx.t), u(target.id), u(source.source)});
  return batch.add_es_step({share(source.theta), target.env, target.optimizer.sigma, step_key},
                           ctx.settings.es.perturbations);
}

// The proposals made from the ES steps in `stepped_batch` (made with the target's lr and Adam moments), run in
// one batch of their evaluations.
std::vector<std::vector<Candidate>> run_proposals(IterationContext& ctx, const std::vector<size_t>& active,
                                                  const RolloutBatch& stepped_batch,
                                                  const std::vector<std::vector<const Candidate*>>& stepped,
                                                  const std::vector<std::vector<size_t>>& es_handles) {
  std::vector<std::vector<Candidate>> proposals(active.size());
  RolloutBatch batch = ctx.batch();
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
      const size_t handle = batch.add_evaluation(share(theta), target.env, eval_key);
      proposals[a].push_back({d.source, true, std::move(theta), handle, {}});
    }
  }
  batch.run(ctx.evaluator, ctx.state.counters);
  for (auto& list : proposals)
    for (Candidate& c : list) c.evaluation = batch.evaluation(c.eval);
  return proposals;
}

// The full test (the paper's): each source directly and as a one-step proposal, in two batches (the direct
// evaluations with the proposals' ES rollouts, then the proposals' evaluations); all compete against the
// target's latest score.
Round full_test(IterationContext& ctx, const std::vector<size_t>& active) {
  RolloutBatch first = ctx.batch();
  std::vector<std::vector<Candidate>> direct = add_direct(ctx, active, first);
  std::vector<std::vector<const Candidate*>> stepped(active.size());
  std::vector<std::vector<size_t>> es_handles(active.size());
  for (size_t a = 0; a < active.size(); ++a) {
    for (const Candidate& d : direct[a]) {
      stepped[a].push_back(&d);
      es_handles[a].push_back(add_step(ctx, first, ctx.state.pairs[active[a]], d));
    }
  }
  first.run(ctx.evaluator, ctx.state.counters, ctx.settings.es);
  std::vector<std::vector<Candidate>> proposals = run_proposals(ctx, active, first, stepped, es_handles);
  Round round;
  for (size_t a = 0; a < active.size(); ++a) {
    Contest contest{{}, ctx.state.pairs[active[a]].latest_score};
    for (Candidate& d : direct[a]) {
      d.evaluation = first.evaluation(d.eval);
      contest.entries.push_back(std::move(d));
    }
    round.proposals += proposals[a].size();
    for (Candidate& p : proposals[a]) contest.entries.push_back(std::move(p));
    round.contests.push_back(std::move(contest));
  }
  return round;
}

// The threshold test (Enhanced POET's): direct evaluations first; only a source that beats the target's threshold
// (the best of its last five evaluation scores) gets the proposal step — two more batches — and the proposals
// alone compete, against the threshold.
Round threshold_test(IterationContext& ctx, const std::vector<size_t>& active) {
  RolloutBatch first = ctx.batch();
  const std::vector<std::vector<Candidate>> direct = add_direct(ctx, active, first);
  first.run(ctx.evaluator, ctx.state.counters, ctx.settings.es);
  std::vector<std::vector<const Candidate*>> stepped(active.size());
  std::vector<std::vector<size_t>> es_handles(active.size());
  RolloutBatch screened = ctx.batch();
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& target = ctx.state.pairs[active[a]];
    for (const Candidate& d : direct[a]) {
      if (!(first.evaluation(d.eval).score > threshold_of(target))) continue;
      stepped[a].push_back(&d);
      es_handles[a].push_back(add_step(ctx, screened, target, d));
    }
  }
  screened.run(ctx.evaluator, ctx.state.counters, ctx.settings.es);
  std::vector<std::vector<Candidate>> proposals = run_proposals(ctx, active, screened, stepped, es_handles);
  Round round;
  for (size_t a = 0; a < active.size(); ++a) {
    round.proposals += proposals[a].size();
    round.contests.push_back({std::move(proposals[a]), threshold_of(ctx.state.pairs[active[a]])});
  }
  return round;
}

// The best candidate of a contest, first in order on ties, if it beats the bar strictly.
const Candidate* winner(const Contest& contest) {
  const Candidate* best = nullptr;
  for (const Candidate& c : contest.entries)
    if (!best || c.evaluation.score > best->evaluation.score) best = &c;
  return best && best->evaluation.score > contest.bar ? best : nullptr;
}

// With confirm_transfers (stochastic courses), each choice and the target's θ run on the same fresh courses, and
// the choice stands only if it scores above θ there; its score is then that one, from courses that did not choose
// it. Returns how many choices were not confirmed.
int64_t confirm(IterationContext& ctx, const std::vector<size_t>& active, std::vector<const Candidate*>& chosen,
                std::vector<Evaluation>& chosen_eval) {
  int64_t unconfirmed = 0;
  RolloutBatch batch = ctx.batch();
  std::vector<std::pair<size_t, size_t>> handles(active.size());
  for (size_t a = 0; a < active.size(); ++a) {
    if (!chosen[a]) continue;
    const Pair& target = ctx.state.pairs[active[a]];
    const uint64_t key = ctx.key("transfer-confirm", {u(ctx.t), u(target.id)});
    handles[a] = {batch.add_evaluation(share(chosen[a]->theta), target.env, key),
                  batch.add_evaluation(share(target.theta), target.env, key)};
  }
  batch.run(ctx.evaluator, ctx.state.counters);
  for (size_t a = 0; a < active.size(); ++a) {
    if (!chosen[a]) continue;
    const Evaluation candidate = batch.evaluation(handles[a].first);
    if (candidate.score > batch.evaluation(handles[a].second).score) {
      chosen_eval[a] = candidate;
    } else {
      chosen[a] = nullptr;
      unconfirmed += 1;
    }
  }
  return unconfirmed;
}

}  // namespace

void transfer(IterationContext& ctx) {
  const int interval = ctx.settings.poet.transfer_interval;
  const std::vector<size_t> active = ctx.state.active_indices();
  if (ctx.t % interval != 0 || active.size() < 2) return;
  ctx.phase(IterationPhase::kTransfer);
  const bool full = ctx.settings.poet.transfer_test == TransferTest::kFull;
  const int64_t rollouts_before = ctx.state.counters.rollouts;
  const Round round = full ? full_test(ctx, active) : threshold_test(ctx, active);

  // the choices; all evaluations used the θs as they stood before the round, and the replacements are applied
  // together afterwards
  std::vector<const Candidate*> chosen(active.size(), nullptr);
  std::vector<Evaluation> chosen_eval(active.size());
  for (size_t a = 0; a < active.size(); ++a) {
    ctx.state.pairs[active[a]].transfer_attempts += 1;
    ctx.state.counters.transfer_attempts += 1;
    chosen[a] = winner(round.contests[a]);
    if (chosen[a]) chosen_eval[a] = chosen[a]->evaluation;
  }
  std::optional<int64_t> unconfirmed;
  if (ctx.settings.poet.confirm_transfers) unconfirmed = confirm(ctx, active, chosen, chosen_eval);

  const int64_t successes_before = ctx.state.counters.transfer_successes;
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
    record_evaluation(ctx, target, target.theta, chosen_eval[a], SolvedBy::kTransfer);
  }
  // what the round cost: with the threshold test, the proposals it paid for out of the N(N−1) of the full test
  ctx.event(TransferRoundEvent{full, active.size(), active.size() * (active.size() - 1), round.proposals,
                               ctx.state.counters.transfer_successes - successes_before,
                               ctx.state.counters.rollouts - rollouts_before, unconfirmed});
}

}  // namespace poet
