#include "simulation/envgen/mutation.h"

#include <cmath>

#include "simulation/envgen/cppn_mutation.h"

namespace poet {

double round1(double x) { return std::nearbyint(x * 10.0) / 10.0; }

double mutated_roughness(double r, double u) {
  const double rounded = round1(r + u);
  if (rounded > kMaxMutatedRoughness) return kMaxMutatedRoughness;
  if (rounded <= 0.0) return 0.0;  // `<=` also turns round1's −0.0 into +0.0, as the reference does
  return rounded;
}

std::vector<Interval> legal_moves(const Interval& gene, const IntervalRule& rule) {
  const double changes[] = {rule.step, 0.0, -rule.step};
  std::vector<Interval> moves;
  for (double change0 : changes) {
    const double lo = round1(gene.lo + change0);
    if (lo > rule.max || lo < rule.initial.lo) continue;
    for (double change1 : changes) {
      const double hi = round1(gene.hi + change1);
      if (hi > rule.max || hi < rule.initial.hi) continue;
      if (change0 == 0.0 && change1 == 0.0) continue;
      if (lo + rule.min_width > hi) continue;
      moves.push_back({lo, hi});
    }
  }
  return moves;
}

Interval mutate_interval(const std::optional<Interval>& gene, const IntervalRule& rule, RandomStream& stream) {
  if (!gene) return rule.initial;
  const std::vector<Interval> moves = legal_moves(*gene, rule);
  if (moves.empty()) return *gene;
  return moves[static_cast<size_t>(stream.uniform_int(0, static_cast<int64_t>(moves.size())))];
}

EnvEncoding mutate(const EnvEncoding& parent, const MutationOptions& options, RandomStream& stream) {
  EnvEncoding child = parent;
  // in "some" mode the coin for a type is drawn right before the type, so draws stay in one fixed order
  auto chosen = [&](bool enabled) { return enabled && (options.all_types || stream.uniform01() < 0.5); };

  if (chosen(options.roughness)) {
    child.roughness = mutated_roughness(parent.roughness, stream.uniform(-kRoughnessStep, kRoughnessStep));
  }

  if (chosen(options.pits)) child.pit_gap = mutate_interval(parent.pit_gap, kPitGapRule, stream);

  if (chosen(options.stumps)) {
    // a new stump type starts wholly at its initial values; an existing one changes only its height
    const bool appear = !parent.has_stumps();
    if (appear) child.stump_width = kStumpWidthOnAppear;
    child.stump_height = mutate_interval(appear ? std::nullopt : parent.stump_height, kStumpHeightRule, stream);
    child.stump_float = kStumpFloat;
  }

  if (chosen(options.stairs)) {
    // step count before height: the reference's order when both change
    const bool appear = !parent.has_stairs();
    if (appear || options.mutate_stair_steps)
      child.stair_steps = mutate_interval(appear ? std::nullopt : parent.stair_steps, kStairStepsRule, stream);
    child.stair_height = mutate_interval(appear ? std::nullopt : parent.stair_height, kStairHeightRule, stream);
    child.stair_width = kStairWidth;
  }

  child.name = reference_name(child);
  return child;
}

EnvDef mutate_def(const EnvDef& parent, const MutationOptions& options, RandomStream& stream) {
  EnvDef child;
  if (parent.encoding.is_cppn()) {
    CppnGenome genome = mutate_cppn(*parent.encoding.cppn, stream);
    child.encoding.name = cppn_name(genome);
    child.encoding.cppn = std::make_shared<const CppnGenome>(std::move(genome));
  } else {
    child.encoding = mutate(parent.encoding, options, stream);
  }
  child.seed = static_cast<uint32_t>(stream.uniform_int(0, kMaxEnvSeed));
  return child;
}

}  // namespace poet
