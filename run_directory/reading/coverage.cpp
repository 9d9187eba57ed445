#include "run_directory/reading/coverage.h"

#include <algorithm>

#include "simulation/envgen/level_sample.h"
#include "simulation/rng.h"

namespace poet {

std::vector<CoverageSample> coverage_sample(uint64_t seed, int per_level) {
  std::vector<CoverageSample> samples;
  for (int level = 1; level <= 3; ++level) {
    RandomStream stream(stream_key(seed, "coverage", {static_cast<uint64_t>(level)}));
    for (int n = 0; n < per_level; ++n)
      samples.push_back({level, draw_env_vector(stream, static_cast<Difficulty>(level)), std::nullopt});
  }
  return samples;
}

Coverage compute_coverage(const RunState& state, uint64_t seed, int per_level) {
  Coverage c;
  c.seed = seed;
  c.per_level = per_level;
  for (const Pair& p : state.pairs)
    if (p.solved() && difficulty(p.env.encoding) != Difficulty::kEasy) c.solved.push_back(env_vector(p.env.encoding));
  c.samples = coverage_sample(seed, per_level);
  if (c.solved.empty()) return c;
  for (CoverageSample& s : c.samples) {
    double nearest = normalized_distance(s.e, c.solved.front());
    for (const EnvVector& v : c.solved) nearest = std::min(nearest, normalized_distance(s.e, v));
    s.distance = nearest;
    std::optional<double>& sum = c.sum[static_cast<size_t>(s.level - 1)];
    sum = sum.value_or(0.0) + nearest;
  }
  return c;
}

}  // namespace poet
