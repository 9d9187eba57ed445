// The direct-path curriculum: step_toward() and the per-iteration stage logic (advance at the threshold, stop
// when the target is solved or the ES-step budget is spent); and ES alone's stop when solved, the same rule.

#include "engine/curriculum.h"

#include <algorithm>
#include <stdexcept>

#include "engine/iteration_context.h"
#include "simulation/envgen/env_distance.h"
#include "simulation/envgen/mutation.h"

namespace poet {
namespace {

// Increases a gene by its step with probability 1/2, clamped at the target's value.
double step_value(double value, double step, double target, RandomStream& stream) {
  if (stream.uniform01() >= 0.5) return value;
  return std::min(round1(value + step), target);
}

// A moving interval gene of a type present in the target.
void step_interval(std::optional<Interval>& gene, const Interval& target, const IntervalRule& rule,
                   RandomStream& stream) {
  if (!gene) {
    if (stream.uniform01() < 0.5)
      gene = Interval{std::min(rule.initial.lo, target.lo), std::min(rule.initial.hi, target.hi)};
    return;
  }
  gene->lo = step_value(gene->lo, rule.step, target.lo, stream);
  gene->hi = step_value(gene->hi, rule.step, target.hi, stream);
  gene->hi = std::min(std::max(gene->hi, gene->lo + rule.min_width), target.hi);  // keep a legal interval
}

EnvEncoding step_once(const EnvEncoding& current, const EnvEncoding& target, RandomStream& stream) {
  EnvEncoding next = current;
  next.roughness = step_value(current.roughness, kRoughnessStep, target.roughness, stream);
  if (target.has_pits()) step_interval(next.pit_gap, *target.pit_gap, kPitGapRule, stream);
  if (target.has_stumps()) {
    step_interval(next.stump_height, *target.stump_height, kStumpHeightRule, stream);
    if (next.stump_height) {
      next.stump_width = target.stump_width;
      next.stump_float = target.stump_float;
    }
  }
  if (target.has_stairs()) {
    step_interval(next.stair_height, *target.stair_height, kStairHeightRule, stream);
    if (next.stair_height) {  // the step count is set when stairs appear and kept, as mutation does
      next.stair_width = target.stair_width;
      next.stair_steps = target.stair_steps;
    }
  }
  return next;
}

}  // namespace

EnvEncoding step_toward(const EnvEncoding& current, const EnvEncoding& target, RandomStream& stream) {
  if (current.same_genes(target)) throw std::invalid_argument("step_toward: already at the target");
  for (;;) {
    EnvEncoding next = step_once(current, target, stream);
    if (!next.same_genes(current)) {
      next.name = reference_name(next);
      return next;
    }
  }
}

void advance_curriculum(IterationContext& ctx) {
  RunState& state = ctx.state;
  Pair& pair = state.pairs.front();
  CurriculumStage& stage = state.stages.back();
  const RunSettings& settings = ctx.settings;
  const EnvDef target = settings.target.value();

  const bool solved_here = pair.latest_finished && pair.latest_score >= settings.poet.solved_score;
  if (solved_here && stage.solved_iteration == kNone) {
    stage.solved_iteration = ctx.t;
    ctx.event(StageEvent{true, state.stages.size() - 1, stage.env.encoding.name,
                         normalized_distance(stage.env.encoding, target.encoding)});
  }
  const bool at_target = pair.env.encoding.same_genes(target.encoding);
  if (at_target && stage.solved_iteration != kNone) {
    state.finished = true;
    ctx.event(RunFinishedEvent{true, pair.es_steps});
    return;
  }
  if (pair.es_steps >= settings.budget_es_steps) {
    state.finished = true;
    ctx.event(RunFinishedEvent{false, pair.es_steps});
    return;
  }
  if (!at_target && pair.latest_score >= settings.advance_threshold) {
    RandomStream stream(ctx.key("direct-path", {static_cast<uint64_t>(state.stages.size())}));
    pair.env = EnvDef{step_toward(pair.env.encoding, target.encoding, stream), target.seed};
    state.stages.push_back({pair.env, ctx.t + 1, kNone});
    ctx.event(StageEvent{false, state.stages.size() - 1, pair.env.encoding.name,
                         normalized_distance(pair.env.encoding, target.encoding)});
  }
}

void finish_if_solved(IterationContext& ctx) {
  // the pair's course is the target, so the pair's first solve (record_evaluation's rule) is the target's
  const Pair& pair = ctx.state.pairs.front();
  if (!pair.solved()) return;
  ctx.state.finished = true;
  ctx.event(RunFinishedEvent{true, pair.es_steps});
}

}  // namespace poet
