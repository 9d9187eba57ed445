#pragma once
// Walkers stepped together on a team of threads, in C++: the vector env behind VectorWalkerEnv. Gymnasium's
// next-step autoreset: the step after a walker's episode ends resets that walker (its action ignored) and reports
// its first observation with reward 0, neither terminated nor truncated. Walker i runs courses[i % courses.size()].
// Walker i's numbers never depend on the thread count. One caller at a time; the caller may release the GIL around
// reset() and step(), which touch nothing of Python.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "python/course_spec.h"
#include "python/episode_env.h"
#include "python/thread_team.h"

namespace poet::python {

class VectorEnv {
 public:
  // walkers >= 1 and threads >= 1 (no more threads are started than walkers), as int_args.h checks them; courses
  // empty is std::invalid_argument.
  VectorEnv(const std::vector<CourseSpec>& courses, int walkers, int threads, WalkerOptions options, int max_steps);

  // A new episode for every walker: walker i on terrain seed first_seed + i (each below kMaxEnvSeed: the caller's
  // to check), or on its course's seed when none is given. Every walker's last step becomes "none yet".
  void reset(std::optional<uint32_t> first_seed = std::nullopt);
  // One step of every walker, actions[i] for walker i (finite; as many as walkers, else std::invalid_argument);
  // std::logic_error before the first reset. The steps are last_steps().
  const std::vector<EpisodeStep>& step(const std::vector<Action>& actions);

  int size() const { return static_cast<int>(walkers_.size()); }
  const EpisodeEnv& walker(size_t i) const { return walkers_[i]; }
  // Each walker's outcome at the last step (all zero after reset, and for a walker the step reset).
  const std::vector<EpisodeStep>& last_steps() const { return steps_; }

 private:
  std::vector<EpisodeEnv> walkers_;
  std::vector<EpisodeStep> steps_;  // written by walker i's thread into slot i only
  ThreadTeam team_;                 // kept between steps: starting threads each step would cost a fifth of a step
  bool started_ = false;
};

}  // namespace poet::python
