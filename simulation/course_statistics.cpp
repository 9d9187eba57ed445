#include "simulation/course_statistics.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "simulation/parallel_for.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"
#include "simulation/rollout.h"

namespace poet {
namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

TerrainStatistics terrain_statistics(const EnvEncoding& encoding, uint32_t first_seed, int count) {
  TerrainStatistics s;
  double pit_width = 0, stump_height = 0;
  for (int n = 0; n < count; ++n) {
    const Terrain t = Terrain::generate({encoding, first_seed + static_cast<uint32_t>(n)});
    const auto& g = t.ground();
    double dy = 0;
    for (size_t i = 1; i < g.size(); ++i) dy += std::abs(g[i].y - g[i - 1].y);
    s.mean_abs_dy += dy / static_cast<double>(g.size() - 1);
    for (const ObstacleFeature& f : t.features()) {
      if (f.kind == ObstacleKind::kPitWall) s.pits += 1, pit_width += f.width;
      if (f.kind == ObstacleKind::kStump) s.stumps += 1, stump_height += f.height;
      if (f.kind == ObstacleKind::kStair) s.stairs += 1;
    }
  }
  if (s.pits > 0) s.mean_pit_width = pit_width / s.pits;
  if (s.stumps > 0) s.mean_stump_height = stump_height / s.stumps;
  s.mean_abs_dy /= count;
  s.pits /= count;
  s.stumps /= count;
  s.stairs /= count;
  s.obstacles = s.pits + s.stumps + s.stairs;
  return s;
}

RandomPolicyStatistics random_policy_statistics(const EnvEncoding& encoding, int policies, uint64_t seed,
                                                const WalkerOptions& options, int threads) {
  std::vector<RolloutResult> results(static_cast<size_t>(policies));
  parallel_for(policies, threads, [&](int i) {
    RandomStream rng(stream_key(seed, "init", {static_cast<uint64_t>(i)}));
    const Terrain terrain = Terrain::generate({encoding, static_cast<uint32_t>(i % 50)});
    results[static_cast<size_t>(i)] = rollout(Mlp(random_params(rng)), terrain, options);
  });
  RandomPolicyStatistics s;
  std::vector<double> returns, steps;
  for (const RolloutResult& r : results) {
    returns.push_back(r.total_reward);
    steps.push_back(r.steps);
    s.fell += r.fell;
    s.timed_out += r.timed_out();
    s.finished += r.finished;
  }
  s.median_return = median(returns);
  s.median_steps = median(steps);
  s.fell /= policies;
  s.timed_out /= policies;
  s.finished /= policies;
  return s;
}

}  // namespace poet
