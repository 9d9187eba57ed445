#include "common/formats/rollout_task_proto.h"

#include <array>
#include <bit>
#include <cmath>
#include <string>

#include "common/formats/envgen/env_proto.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {
namespace {

// The limits a run config accepts (run_config.cpp), so a task from the network is never worse than a config.
constexpr double kMaxPushScale = 1000;
constexpr int kMaxSteps = 100'000;

}  // namespace

uint64_t theta_hash(std::span<const double> theta) {
  // Four chains, each over every fourth value, so that the mixing of one overlaps the others': a worker hashes
  // every θ it is sent, and one chain of 2,804 dependent mixes took 9 µs (four: 3.4).
  const size_t n = theta.size();
  std::array<uint64_t, 4> lane{mix64(n), mix64(n + 1), mix64(n + 2), mix64(n + 3)};
  size_t i = 0;
  for (; i + 4 <= n; i += 4)
    for (size_t k = 0; k < 4; ++k) lane[k] = mix64(lane[k] ^ std::bit_cast<uint64_t>(theta[i + k]));
  for (size_t k = 0; i < n; ++i, ++k) lane[k] = mix64(lane[k] ^ std::bit_cast<uint64_t>(theta[i]));
  return mix64(lane[0] ^ mix64(lane[1] ^ mix64(lane[2] ^ mix64(lane[3]))));
}

wire::Task to_wire(const RolloutTask& task, uint64_t hash) {
  wire::Task out;
  out.set_theta_hash(hash);
  if (task.perturbation) {
    out.set_perturbation_key(task.perturbation->key);
    out.set_sign(task.perturbation->sign);
    out.set_sigma(task.perturbation->sigma);
  }
  *out.mutable_env() = to_proto(task.env);
  out.set_push_scale(task.walker.push_scale);
  out.set_lidar(task.walker.lidar == LidarRule::kFirst ? pb::WalkerConfig::FIRST : pb::WalkerConfig::NEAREST);
  out.set_max_steps(task.max_steps);
  return out;
}

wire::TaskResult to_wire(const RolloutResult& result) {
  wire::TaskResult out;
  out.set_total_reward(result.total_reward);
  out.set_steps(result.steps);
  out.set_finished(result.finished);
  out.set_fell(result.fell);
  return out;
}

std::optional<std::string> add_theta(const wire::Theta& message, ThetaCache& cache) {
  if (!message.has_hash()) return std::string("hash: missing");
  if (message.values_size() != kParamCount)
    return "values: " + std::to_string(message.values_size()) + " values, expected " + std::to_string(kParamCount);
  for (int i = 0; i < message.values_size(); ++i)
    if (!std::isfinite(message.values(i))) return "values[" + std::to_string(i) + "]: not finite";
  auto theta = std::make_shared<const std::vector<double>>(message.values().begin(), message.values().end());
  if (theta_hash(*theta) != message.hash()) return std::string("hash: does not match the values");
  cache[message.hash()] = std::move(theta);
  return std::nullopt;
}

Expected<RolloutTask> task_from_wire(const wire::Task& message, const ThetaCache& cache) {
  RolloutTask task;
  const auto theta = cache.find(message.theta_hash());
  if (!message.has_theta_hash() || theta == cache.end()) return Unexpected{"theta_hash: no θ with this hash was sent"};
  task.theta = theta->second;
  if (message.has_perturbation_key()) {
    if (message.sign() != 1 && message.sign() != -1)
      return Unexpected{"sign: must be +1 or -1 (got " + std::to_string(message.sign()) + ")"};
    if (!std::isfinite(message.sigma()) || message.sigma() < 0 || message.sigma() > 10)
      return Unexpected{"sigma: must be in [0, 10]"};
    task.perturbation = Perturbation{message.perturbation_key(), message.sign(), message.sigma()};
  }
  if (!message.has_env()) return Unexpected{"env: missing"};
  Expected<EnvDef> env = env_def_from_proto(message.env());
  if (!env) return Unexpected{"env." + env.error()};
  task.env = std::move(*env);
  if (!std::isfinite(message.push_scale()) || message.push_scale() < 0 || message.push_scale() > kMaxPushScale)
    return Unexpected{"push_scale: must be in [0, 1000]"};
  if (!pb::WalkerConfig::LidarRule_IsValid(message.lidar())) return Unexpected{"lidar: unknown rule"};
  task.walker.push_scale = message.push_scale();
  task.walker.lidar = message.lidar() == pb::WalkerConfig::FIRST ? LidarRule::kFirst : LidarRule::kNearest;
  if (message.max_steps() < 1 || message.max_steps() > kMaxSteps)
    return Unexpected{"max_steps: must be in [1, 100000] (got " + std::to_string(message.max_steps()) + ")"};
  task.max_steps = message.max_steps();
  return task;
}

Expected<RolloutResult> result_from_wire(const wire::TaskResult& message) {
  if (!std::isfinite(message.total_reward())) return Unexpected{"total_reward: not finite"};
  if (message.steps() < 0) return Unexpected{"steps: negative"};
  RolloutResult r;
  r.total_reward = message.total_reward();
  r.steps = message.steps();
  r.finished = message.finished();
  r.fell = message.fell();
  return r;
}

std::optional<std::vector<RolloutResult>> results_from_wire(const wire::Result& message, size_t count) {
  if (message.results_size() != static_cast<int>(count)) return std::nullopt;
  std::vector<RolloutResult> parsed;
  parsed.reserve(count);
  for (const wire::TaskResult& one : message.results()) {
    Expected<RolloutResult> r = result_from_wire(one);
    if (!r) return std::nullopt;
    parsed.push_back(std::move(*r));
  }
  return parsed;
}

}  // namespace poet
