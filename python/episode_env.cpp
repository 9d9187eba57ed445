#include "python/episode_env.h"

#include <stdexcept>

namespace poet::python {

EpisodeEnv::EpisodeEnv(CourseSpec course, std::optional<uint32_t> seed, WalkerOptions options, int max_steps)
    : encoding_(std::move(course.encoding)),
      seed_(seed.value_or(course.seed.value_or(0))),
      options_(options),
      max_steps_(max_steps) {
  if (max_steps < 1) throw std::invalid_argument("max_steps must be at least 1, got " + std::to_string(max_steps));
}

const Observation& EpisodeEnv::reset(std::optional<uint32_t> seed) {
  if (seed) seed_ = *seed;
  env_.reset();  // the world refers to the terrain: it goes first
  terrain_ = std::make_unique<Terrain>(Terrain::generate({encoding_, seed_}));
  env_ = std::make_unique<WalkerEnv>(*terrain_, options_);
  steps_ = 0;
  running_ = true;
  return env_->reset();
}

EpisodeStep EpisodeEnv::step(const Action& action) {
  if (!running_)
    throw std::logic_error(env_ ? "step() after the episode ended: call reset() first"
                                : "step() before reset(): call reset() first");
  const StepOutcome out = env_->step(action);
  steps_ += 1;
  EpisodeStep s;
  s.reward = out.reward;
  s.finished = out.finished;
  s.fell = out.fell;
  s.terminated = out.done();
  s.truncated = !s.terminated && steps_ >= max_steps_;
  running_ = !(s.terminated || s.truncated);
  return s;
}

}  // namespace poet::python
