#include "python/vector_env.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace poet::python {
namespace {

// The team's size, checked before any walker is made: no more threads than walkers.
int team_size(const std::vector<CourseSpec>& courses, int walkers, int threads) {
  if (courses.empty()) throw std::invalid_argument("courses must name at least one course");
  if (walkers < 1) throw std::invalid_argument("num_envs must be at least 1, got " + std::to_string(walkers));
  if (threads < 1) throw std::invalid_argument("threads must be at least 1, got " + std::to_string(threads));
  return std::min(threads, walkers);
}

}  // namespace

VectorEnv::VectorEnv(const std::vector<CourseSpec>& courses, int walkers, int threads, WalkerOptions options,
                     int max_steps)
    : team_(team_size(courses, walkers, threads)) {
  walkers_.reserve(static_cast<size_t>(walkers));
  for (size_t i = 0; i < static_cast<size_t>(walkers); ++i)
    walkers_.emplace_back(courses[i % courses.size()], std::nullopt, options, max_steps);
  steps_.assign(walkers_.size(), EpisodeStep{});
}

void VectorEnv::reset(std::optional<uint32_t> first_seed) {
  team_.run(size(), [&](int k) {
    const auto i = static_cast<size_t>(k);
    walkers_[i].reset(first_seed ? std::optional(*first_seed + static_cast<uint32_t>(i)) : std::nullopt);
  });
  steps_.assign(walkers_.size(), EpisodeStep{});
  started_ = true;
}

const std::vector<EpisodeStep>& VectorEnv::step(const std::vector<Action>& actions) {
  if (!started_) throw std::logic_error("step() before reset(): call reset() first");
  if (actions.size() != walkers_.size())
    throw std::invalid_argument("actions: " + std::to_string(actions.size()) + " rows for " +
                                std::to_string(walkers_.size()) + " walkers");
  team_.run(size(), [&](int k) {
    const auto i = static_cast<size_t>(k);
    // a walker whose episode ended at the last step starts its next one instead of stepping
    const bool ended = steps_[i].terminated || steps_[i].truncated;
    if (ended) {
      walkers_[i].reset();
      steps_[i] = EpisodeStep{};
      return;
    }
    steps_[i] = walkers_[i].step(actions[i]);
  });
  return steps_;
}

}  // namespace poet::python
