#pragma once
// Coverage (spec §3, the paper's §5): a seeded sample of environments at each of the three difficulty levels
// above easy, drawn uniformly in the box e ∈ [0,8]×[0,8]×[0,8]×[0,3]×[0,3] with lo ≤ hi for both intervals
// (rejection-sampled to lo ≤ hi and then to the level), and for each sample the normalised distance to the
// nearest environment the run solved at a level of challenging or above. Lower sums are better. The sample is
// a function of (seed, per_level) alone, so runs compared on the same seed are compared on the same sample.

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "engine/run_state.h"
#include "simulation/envgen/env_distance.h"

namespace poet {

struct CoverageSample {
  int level = 1;  // Difficulty 1..3
  EnvVector e{};
  std::optional<double> distance;  // nullopt: the run solved nothing at challenging or above
};

struct Coverage {
  uint64_t seed = 0;
  int per_level = 0;
  std::vector<EnvVector> solved;               // the run's solved environments at challenging or above
  std::vector<CoverageSample> samples;         // per_level of level 1, then of 2, then of 3
  std::array<std::optional<double>, 3> sum{};  // per level 1..3; nullopt when nothing qualifies
};

inline constexpr uint64_t kDefaultCoverageSeed = 20190101;
inline constexpr int kDefaultCoveragePerLevel = 1000;  // the paper's sample size

// The seeded sample alone (per_level samples at each of levels 1..3).
std::vector<CoverageSample> coverage_sample(uint64_t seed, int per_level);

Coverage compute_coverage(const RunState& state, uint64_t seed = kDefaultCoverageSeed,
                          int per_level = kDefaultCoveragePerLevel);

}  // namespace poet
