#include "engine/engine.h"

#include <cmath>
#include <string>

#include "engine/iteration_context.h"
#include "simulation/envgen/cppn_mutation.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {

uint64_t IterationContext::key(std::string_view purpose, std::initializer_list<uint64_t> ids) const {
  return stream_key(settings.seed, purpose, ids);
}

IterationContext iteration_context(RunState& state, Evaluator& evaluator, IterationReport& report) {
  return {state, evaluator, report, state.settings, state.next_iteration};
}

void record_evaluation(IterationContext& ctx, Pair& pair, const std::vector<double>& theta, const Evaluation& eval,
                       SolvedBy by) {
  pair.latest_score = eval.score;
  pair.latest_finished = eval.finished;
  if (ctx.settings.poet.transfer_test == TransferTest::kThreshold) {
    pair.recent_scores.push_back(eval.score);
    if (pair.recent_scores.size() > kRecentScores) pair.recent_scores.erase(pair.recent_scores.begin());
  }
  if (pair.best_iteration == kNone || eval.score > pair.best_score) {
    pair.best_score = eval.score;
    pair.best_theta = theta;
    pair.best_iteration = ctx.t;
  }
  if (!pair.solved() && eval.finished && eval.score >= ctx.settings.poet.solved_score) {
    pair.first_solved_iteration = ctx.t;
    ctx.event(SolvedEvent{pair.id, pair.env.encoding.name, eval.score, ctx.t - pair.created_iteration, by});
  }
}

void require_finite(const IterationContext& ctx, const Pair& pair, std::span<const double> values,
                    std::string_view what) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) continue;
    throw RunDiverged("the run diverged at iteration " + std::to_string(ctx.t) + ": pair " + std::to_string(pair.id) +
                      " (" + pair.env.encoding.name + "), " + std::string(what) + ": element " + std::to_string(i) +
                      " is " + std::to_string(values[i]) +
                      ". A run is a function of its config, so resuming from the last checkpoint will repeat this; "
                      "start a new run with smaller es.init_lr, es.init_sigma or es.l2_coeff");
  }
}

std::vector<double> propose(ProposalKind kind, const std::vector<double>& theta, const std::vector<double>& g,
                            const OptimizerState& optimizer, double lr, const EsSettings& es) {
  if (kind == ProposalKind::kAdam) return adam_proposal(theta, g, optimizer, lr, es);
  return sgd_proposal(theta, g, lr, es.l2_coeff);
}

namespace {

// A POET run's first environment: flat, or a first CPPN genome drawn from the run's "first-cppn" stream.
EnvEncoding first_environment(const RunSettings& settings) {
  if (settings.poet.environments == EnvironmentKind::kObstacleCourses) return named_course("flat").value();
  RandomStream stream(stream_key(settings.seed, "first-cppn"));
  EnvEncoding encoding;
  encoding.cppn = std::make_shared<const CppnGenome>(first_cppn_genome(stream));
  encoding.name = cppn_name(*encoding.cppn);
  return encoding;
}

}  // namespace

RunState initial_state(const RunSettings& settings, std::optional<std::vector<double>> start_theta) {
  RunState state;
  state.settings = settings;

  Pair first;
  first.id = state.next_pair_id++;
  switch (settings.mode) {
    case RunMode::kEsAlone:
      first.env = settings.target.value();
      break;
    case RunMode::kDirectPath:
      first.env = EnvDef{named_course("flat").value(), settings.target.value().seed};
      break;
    default:
      first.env = EnvDef{first_environment(settings), static_cast<uint32_t>(settings.seed % kMaxEnvSeed)};
  }
  if (start_theta) {
    first.theta = std::move(*start_theta);
  } else if (settings.init_zero) {
    first.theta = zero_params();
  } else {
    RandomStream init(stream_key(settings.seed, "init", {0}));
    first.theta = random_params(init, settings.init_stddev);
  }
  first.optimizer = fresh_optimizer(settings.es, first.theta.size());
  first.best_theta = first.theta;
  if (settings.mode == RunMode::kDirectPath) state.stages.push_back({first.env, 0, kNone});
  state.pairs.push_back(std::move(first));
  return state;
}

bool budget_reached(const RunState& state) {
  const int64_t budget = state.settings.env_step_budget;
  return budget > 0 && state.counters.env_steps >= budget;
}

bool run_complete(const RunState& state) {
  return state.finished || state.next_iteration >= state.settings.iterations || budget_reached(state);
}

IterationReport run_iteration(RunState& state, Evaluator& evaluator, PhaseObserver* phases) {
  IterationReport report;
  report.iteration = state.next_iteration;
  const int64_t rollouts_before = state.counters.rollouts;
  IterationContext ctx = iteration_context(state, evaluator, report);
  ctx.phases = phases;

  const RunMode mode = state.settings.mode;
  if (mode == RunMode::kPoet || mode == RunMode::kPoetWithoutTransfer) reproduce(ctx);
  optimise(ctx);
  if (mode == RunMode::kPoet) transfer(ctx);
  if (mode == RunMode::kDirectPath) advance_curriculum(ctx);
  if (mode == RunMode::kEsAlone && state.settings.stop_when_solved) finish_if_solved(ctx);

  if (phases) phases->iteration_ends();
  report.annecs = annecs_at(state, report.iteration);
  state.next_iteration += 1;
  report.rollouts = state.counters.rollouts - rollouts_before;
  return report;
}

}  // namespace poet
