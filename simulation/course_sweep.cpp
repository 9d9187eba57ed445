#include "simulation/course_sweep.h"

#include <algorithm>
#include <stdexcept>

#include "simulation/parallel_for.h"

namespace poet {

double CourseSweep::mean_return() const {
  double sum = 0;
  for (const auto& e : episodes) sum += e.total_reward;
  return sum / static_cast<double>(episodes.size());
}

double CourseSweep::min_return() const {
  double m = episodes.front().total_reward;
  for (const auto& e : episodes) m = std::min(m, e.total_reward);
  return m;
}

double CourseSweep::max_return() const {
  double m = episodes.front().total_reward;
  for (const auto& e : episodes) m = std::max(m, e.total_reward);
  return m;
}

int CourseSweep::finished() const {
  return static_cast<int>(std::count_if(episodes.begin(), episodes.end(), [](const auto& e) { return e.finished; }));
}

int CourseSweep::fell() const {
  return static_cast<int>(std::count_if(episodes.begin(), episodes.end(), [](const auto& e) { return e.fell; }));
}

int CourseSweep::timed_out() const {
  return static_cast<int>(std::count_if(episodes.begin(), episodes.end(), [](const auto& e) { return e.timed_out(); }));
}

double CourseSweep::mean_steps() const {
  double sum = 0;
  for (const auto& e : episodes) sum += e.steps;
  return sum / static_cast<double>(episodes.size());
}

CourseSweep sweep_course(const Mlp& policy, const std::string& label, const EnvEncoding& encoding, uint32_t first_seed,
                         int count, const WalkerOptions& options, int max_steps, int threads) {
  if (count < 1) throw std::invalid_argument("sweep: at least one seed is needed");
  if (uint64_t(first_seed) + uint64_t(count) > kMaxEnvSeed)
    throw std::invalid_argument("sweep: terrain seeds must stay below 1000000");
  std::vector<uint32_t> seeds(static_cast<size_t>(count));
  for (size_t i = 0; i < seeds.size(); ++i) seeds[i] = first_seed + static_cast<uint32_t>(i);
  return {label, first_seed, run_episodes(policy, encoding, seeds, options, max_steps, threads)};
}

std::vector<RolloutResult> run_episodes(const Mlp& policy, const EnvEncoding& encoding, std::span<const uint32_t> seeds,
                                        const WalkerOptions& options, int max_steps, int threads) {
  std::vector<RolloutResult> episodes(seeds.size());
  parallel_for(static_cast<int>(seeds.size()), threads, [&](int i) {
    const Terrain terrain = Terrain::generate({encoding, seeds[static_cast<size_t>(i)]});
    episodes[static_cast<size_t>(i)] = rollout(policy, terrain, options, {.max_steps = max_steps});
  });
  return episodes;
}

}  // namespace poet
