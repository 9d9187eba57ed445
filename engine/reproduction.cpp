// Step 1 of an iteration (spec §3): mutate eligible parents' environments into children, keep those that are new
// and pass the minimal criterion, rank them (novelty, by encoding distance or PATA-EC, or score), admit the best
// through the best starting agent among the active pairs, and retire the oldest pairs beyond the cap.

#include <algorithm>
#include <numeric>
#include <optional>
#include <span>

#include "engine/iteration_context.h"
#include "engine/pata_ec.h"
#include "simulation/envgen/env_distance.h"
#include "simulation/envgen/mutation.h"
#include "simulation/rng.h"

namespace poet {
namespace {

struct Child {
  EnvDef env;
  int parent = kNone;  // pair id
  int attempt = 0;     // mutation attempt index: names the child in keys and events
  Evaluation mc;       // the parent's θ on the child
  double novelty = 0;
};

// The best starting agent for a child, and its score.
struct Start {
  int source = kNone;
  bool proposal = false;
  std::vector<double> theta;
  Evaluation eval;
};

bool archived(const RunState& state, const EnvEncoding& encoding) {
  return std::any_of(state.pairs.begin(), state.pairs.end(),
                     [&](const Pair& p) { return p.env.encoding.same_genes(encoding); });
}

// A pair's agent in reproduction and admission (poet.reproduction_agent): its current θ and latest score, or the
// best θ it has had and that θ's score.
const std::vector<double>& agent_theta(const IterationContext& ctx, const Pair& p) {
  const bool best = ctx.settings.poet.reproduction_agent == ReproductionAgent::kBestTheta && !p.best_theta.empty();
  return best ? p.best_theta : p.theta;
}

double agent_score(const IterationContext& ctx, const Pair& p) {
  const bool best = ctx.settings.poet.reproduction_agent == ReproductionAgent::kBestTheta && !p.best_theta.empty();
  return best ? p.best_score : p.latest_score;
}

// The event of a mutation attempt; duplicate, or the minimal-criterion score and verdict, are added when known.
ChildEvent child_event(const Child& child) {
  ChildEvent e;
  e.attempt = child.attempt;
  e.parent = child.parent;
  e.env = child.env.encoding.name;
  e.e = env_vector(child.env.encoding);
  return e;
}

// Step 1.d: for each active pair in creation order, its θ (direct) and then a one-step proposal from it made
// with a fresh optimizer's lr and σ; the first best wins ties. The direct scores come first: when one is above
// the minimal criterion's upper bound, so is the best start whatever the proposals score, and the candidate is
// refused without paying for their ES steps (the same outcome as the full walk, for N ES steps fewer). Returns
// nullopt for such a candidate.
std::optional<Start> best_start(IterationContext& ctx, const Child& child) {
  const auto u = [](auto v) { return static_cast<uint64_t>(v); };
  const std::vector<size_t> active = ctx.state.active_indices();
  const OptimizerState fresh = fresh_optimizer(ctx.settings.es, kParamCount);
  const ProposalKind kind = ctx.settings.poet.admission_proposal;

  RolloutBatch first = ctx.batch();
  std::vector<size_t> direct;
  for (size_t i : active) {
    const Pair& source = ctx.state.pairs[i];
    direct.push_back(first.add_evaluation(share(agent_theta(ctx, source)), child.env,
                                          ctx.key("admission-eval", {u(ctx.t), u(child.attempt), u(source.id), 0})));
  }
  first.run(ctx.evaluator, ctx.state.counters);
  for (size_t d : direct)
    if (first.evaluation(d).score > ctx.settings.poet.mc_high) return std::nullopt;

  RolloutBatch steps_batch = ctx.batch();
  std::vector<size_t> steps;
  for (size_t i : active) {
    const Pair& source = ctx.state.pairs[i];
    steps.push_back(steps_batch.add_es_step({share(agent_theta(ctx, source)), child.env, fresh.sigma,
                                             ctx.key("admission-noise", {u(ctx.t), u(child.attempt), u(source.id)})},
                                            ctx.settings.es.perturbations));
  }
  steps_batch.run(ctx.evaluator, ctx.state.counters, ctx.settings.es);

  RolloutBatch second = ctx.batch();
  std::vector<std::vector<double>> proposals;
  std::vector<size_t> proposal_evals;
  const std::vector<EsOutcome> outcomes = steps_batch.es_outcomes(steps, ctx.settings.es);
  for (size_t s = 0; s < active.size(); ++s) {
    const Pair& source = ctx.state.pairs[active[s]];
    const EsOutcome& out = outcomes[s];
    proposals.push_back(propose(kind, agent_theta(ctx, source), out.gradient, fresh, fresh.lr, ctx.settings.es));
    require_finite(ctx, source, proposals.back(),
                   "its admission proposal for child attempt " + std::to_string(child.attempt));
    proposal_evals.push_back(second.add_evaluation(
        share(proposals.back()), child.env, ctx.key("admission-eval", {u(ctx.t), u(child.attempt), u(source.id), 1})));
  }
  second.run(ctx.evaluator, ctx.state.counters);

  Start best;
  for (size_t s = 0; s < active.size(); ++s) {
    const Pair& source = ctx.state.pairs[active[s]];
    const Evaluation d = first.evaluation(direct[s]);
    if (best.source == kNone || d.score > best.eval.score) best = {source.id, false, agent_theta(ctx, source), d};
    const Evaluation p = second.evaluation(proposal_evals[s]);
    if (p.score > best.eval.score) best = {source.id, true, proposals[s], p};
  }
  return best;
}

// Step 1.c with PATA-EC novelty (Enhanced POET). The agents are every pair's θ, active or retired (a retired
// pair's θ as it stood at retirement), in creation order; the environments, every pair's (the archive) and every
// survivor's. Each agent is evaluated on each of them in one batch, afresh at every reproduction because the
// active agents have moved on since the last. Sets each survivor's novelty against the archive's PATA-ECs, never
// against the other survivors', and returns the number of evaluations; with no survivor nothing is evaluated.
size_t set_pata_ec_novelty(IterationContext& ctx, std::vector<Child>& survivors) {
  if (survivors.empty()) return 0;
  const auto u = [](auto v) { return static_cast<uint64_t>(v); };
  const std::vector<Pair>& pairs = ctx.state.pairs;
  const PoetSettings& poet = ctx.settings.poet;
  std::vector<SharedParams> agents;
  for (const Pair& p : pairs) agents.push_back(share(p.theta));

  // every agent on one environment: an archived pair's (kind 0, its id) or a survivor's (kind 1, its attempt)
  RolloutBatch batch = ctx.batch();
  const auto add_row = [&](const EnvDef& env, uint64_t kind, uint64_t id) {
    std::vector<size_t> row;
    for (size_t a = 0; a < pairs.size(); ++a)
      row.push_back(
          batch.add_evaluation(agents[a], env, ctx.key("pata-ec-eval", {u(ctx.t), kind, id, u(pairs[a].id)})));
    return row;
  };
  std::vector<std::vector<size_t>> rows;  // the archive's, then the survivors'
  for (const Pair& p : pairs) rows.push_back(add_row(p.env, 0, u(p.id)));
  for (const Child& c : survivors) rows.push_back(add_row(c.env, 1, u(c.attempt)));
  batch.run(ctx.evaluator, ctx.state.counters);

  std::vector<PataEc> characterised;
  for (const std::vector<size_t>& row : rows) {
    std::vector<double> scores;
    for (size_t h : row) scores.push_back(batch.evaluation(h).score);
    characterised.push_back(pata_ec(scores, poet.mc_low, poet.mc_high));
  }
  const std::span<const PataEc> archive(characterised.data(), pairs.size());
  for (size_t c = 0; c < survivors.size(); ++c)
    survivors[c].novelty = pata_ec_novelty(characterised[pairs.size() + c], archive, poet.novelty_k);
  return rows.size() * agents.size();
}

void admit(IterationContext& ctx, const Child& child, Start start) {
  RunState& state = ctx.state;
  Pair pair;
  pair.id = state.next_pair_id++;
  pair.env = child.env;
  pair.created_iteration = ctx.t;
  pair.parent_id = child.parent;
  pair.initial_source_pair = start.source;
  pair.initial_by_proposal = start.proposal;
  pair.admission_score = start.eval.score;
  pair.theta = std::move(start.theta);
  pair.optimizer = fresh_optimizer(ctx.settings.es, pair.theta.size());
  state.counters.children_admitted += 1;
  ctx.event(PairCreatedEvent{pair.id, pair.env.encoding.name, pair.env.seed, pair.parent_id, pair.initial_source_pair,
                             pair.initial_by_proposal, pair.admission_score, child.novelty});
  const std::vector<double> theta = pair.theta;
  record_evaluation(ctx, pair, theta, start.eval, SolvedBy::kAdmission);
  state.pairs.push_back(std::move(pair));
}

// Step 1.a: the active pairs whose agent scores at least the reproduction threshold.
std::vector<size_t> eligible_parents(const IterationContext& ctx) {
  std::vector<size_t> eligible;
  for (size_t i : ctx.state.active_indices())
    if (agent_score(ctx, ctx.state.pairs[i]) >= ctx.settings.poet.repro_threshold) eligible.push_back(i);
  return eligible;
}

// Step 1.b's mutation attempts: the children that are new to the archive, and an event per attempt.
struct Attempts {
  std::vector<Child> children;
  std::vector<ChildEvent> events;  // one per attempt, in attempt order
  int duplicates = 0;
};

Attempts mutate_children(IterationContext& ctx, const std::vector<size_t>& eligible) {
  const PoetSettings& poet = ctx.settings.poet;
  RunState& state = ctx.state;
  RandomStream stream(ctx.key("reproduce", {static_cast<uint64_t>(ctx.t)}));
  Attempts out;
  for (int a = 0; a < poet.max_children; ++a) {
    const Pair& parent = state.pairs[eligible[static_cast<size_t>(stream.uniform_int(0, eligible.size()))]];
    Child child{mutate_def(parent.env, poet.mutation, stream), parent.id, a, {}, 0};
    state.counters.children_tried += 1;
    out.events.push_back(child_event(child));
    if (archived(state, child.env.encoding)) {
      out.duplicates += 1;
      out.events.back().duplicate = true;
      continue;
    }
    out.children.push_back(std::move(child));
  }
  return out;
}

// Step 1.b's minimal criterion: each child evaluated with its parent's agent; returns those that pass, after
// the attempts' events (now with their scores and verdicts).
std::vector<Child> pass_minimal_criterion(IterationContext& ctx, Attempts& attempts) {
  const auto u = [](auto v) { return static_cast<uint64_t>(v); };
  const PoetSettings& poet = ctx.settings.poet;
  RunState& state = ctx.state;
  std::vector<Child>& children = attempts.children;
  RolloutBatch mc_batch = ctx.batch();
  std::vector<size_t> mc_handles;
  for (const Child& c : children) {
    const Pair* parent = state.find(c.parent);
    mc_handles.push_back(
        mc_batch.add_evaluation(share(agent_theta(ctx, *parent)), c.env, ctx.key("mc-eval", {u(ctx.t), u(c.attempt)})));
  }
  mc_batch.run(ctx.evaluator, state.counters);
  std::vector<Child> survivors;
  for (size_t c = 0; c < children.size(); ++c) {
    children[c].mc = mc_batch.evaluation(mc_handles[c]);
    const bool passed = poet.passes_mc(children[c].mc.score);
    ChildEvent& event = attempts.events[static_cast<size_t>(children[c].attempt)];
    event.mc_score = children[c].mc.score;
    event.passed_mc = passed;
    if (passed) survivors.push_back(std::move(children[c]));
  }
  for (ChildEvent& event : attempts.events) ctx.event(std::move(event));
  state.counters.children_passed_mc += static_cast<int64_t>(survivors.size());
  return survivors;
}

// Step 1.c: most novel first against the archive (or lowest MC score first); ties keep generation order. Returns
// the number of PATA-EC evaluations when that is the novelty measure.
std::optional<size_t> rank_survivors(IterationContext& ctx, std::vector<Child>& survivors) {
  const PoetSettings& poet = ctx.settings.poet;
  std::optional<size_t> pata_ec_evaluations;
  if (poet.novelty == NoveltyMeasure::kPataEc) {
    pata_ec_evaluations = set_pata_ec_novelty(ctx, survivors);
  } else {
    std::vector<EnvEncoding> archive;
    for (const Pair& p : ctx.state.pairs) archive.push_back(p.env.encoding);
    for (Child& c : survivors) c.novelty = novelty(c.env.encoding, archive, poet.novelty_k, poet.novelty_normalized);
  }
  if (poet.child_ranking == ChildRanking::kLowestScoreFirst) {
    std::stable_sort(survivors.begin(), survivors.end(),
                     [](const Child& a, const Child& b) { return a.mc.score < b.mc.score; });
  } else {
    std::stable_sort(survivors.begin(), survivors.end(),
                     [](const Child& a, const Child& b) { return a.novelty > b.novelty; });
  }
  return pata_ec_evaluations;
}

// Step 1.d: admission in rank order through the best starting agent (or the parent's, without selection), up to
// max_admitted; returns the number admitted.
int admit_survivors(IterationContext& ctx, const std::vector<Child>& survivors) {
  const PoetSettings& poet = ctx.settings.poet;
  const bool select = ctx.settings.mode == RunMode::kPoet || poet.keep_admission_selection;
  int admitted = 0;
  for (const Child& c : survivors) {
    if (admitted >= poet.max_admitted) break;
    if (archived(ctx.state, c.env.encoding)) continue;  // an earlier admission of this walk had the same genes
    Start start;
    if (select) {
      std::optional<Start> found = best_start(ctx, c);
      if (!found || !poet.passes_mc(found->eval.score)) continue;
      start = std::move(*found);
    } else {
      const Pair* parent = ctx.state.find(c.parent);
      start = {parent->id, false, agent_theta(ctx, *parent), c.mc};
    }
    admit(ctx, c, std::move(start));
    admitted += 1;
  }
  return admitted;
}

// Step 1.e, the cap: retire the oldest active pairs.
void retire_beyond_cap(IterationContext& ctx) {
  const std::vector<size_t> active = ctx.state.active_indices();
  for (size_t r = 0; active.size() > static_cast<size_t>(ctx.settings.poet.active_cap) + r; ++r) {
    Pair& old = ctx.state.pairs[active[r]];
    old.retired_iteration = ctx.t;
    ctx.event(PairRetiredEvent{old.id, old.env.encoding.name, old.solved()});
  }
}

}  // namespace

void reproduce(IterationContext& ctx) {
  const PoetSettings& poet = ctx.settings.poet;
  if (ctx.t == 0 || ctx.t % poet.mutation_interval != 0) return;
  ctx.phase(IterationPhase::kReproduction);

  const std::vector<size_t> eligible = eligible_parents(ctx);
  if (eligible.empty()) {
    ctx.event(ReproductionEvent{});
    return;
  }
  Attempts attempts = mutate_children(ctx, eligible);
  std::vector<Child> survivors = pass_minimal_criterion(ctx, attempts);
  const std::optional<size_t> pata_ec_evaluations = rank_survivors(ctx, survivors);
  const int admitted = admit_survivors(ctx, survivors);
  ctx.event(ReproductionEvent{eligible.size(), poet.max_children, attempts.duplicates, survivors.size(), admitted,
                              pata_ec_evaluations});
  retire_beyond_cap(ctx);
}

}  // namespace poet
