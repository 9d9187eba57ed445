#pragma once
// The walker as an episode in Gymnasium's terms, in C++: reset to a course seed, step until terminated (the
// walker fell or finished) or truncated (the time limit). The same steps and rewards as rollout(): an episode of
// a policy here returns what poet-eval reports for it.

#include <cstdint>
#include <memory>
#include <optional>

#include "python/course_spec.h"
#include "simulation/walker/terrain.h"
#include "simulation/walker/walker_env.h"

namespace poet::python {

struct EpisodeStep {
  double reward = 0;
  bool terminated = false;  // fell or finished
  bool truncated = false;   // the time limit, not terminated
  bool finished = false;
  bool fell = false;
};

class EpisodeEnv {
 public:
  // seed: the course's terrain seed (a file's own seed, else 0, when absent).
  EpisodeEnv(CourseSpec course, std::optional<uint32_t> seed, WalkerOptions options, int max_steps);

  // A new episode; a seed replaces the course's terrain seed for this and later episodes.
  const Observation& reset(std::optional<uint32_t> seed = std::nullopt);
  // Throws std::logic_error before the first reset or after the episode ended; the action must be finite.
  EpisodeStep step(const Action& action);

  bool running() const { return running_; }
  int steps() const { return steps_; }
  uint32_t seed() const { return seed_; }
  int max_steps() const { return max_steps_; }
  double hull_x() const { return env_ ? env_->hull_x() : 0.0; }
  const Observation& observation() const { return env_->observation(); }
  const Terrain& terrain() const { return *terrain_; }
  WalkerPose pose() const { return env_->pose(); }
  bool has_episode() const { return env_ != nullptr; }

 private:
  EnvEncoding encoding_;
  uint32_t seed_ = 0;
  WalkerOptions options_;
  int max_steps_ = 0;
  std::unique_ptr<Terrain> terrain_;
  std::unique_ptr<WalkerEnv> env_;
  int steps_ = 0;
  bool running_ = false;
};

}  // namespace poet::python
