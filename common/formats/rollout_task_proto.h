#pragma once
// Rollout tasks and results as wire messages (proto/wire.proto): what a worker receives and sends back. A task
// names its θ by content hash; θ itself travels once per worker and batch. Reading a message is a boundary: a
// task from the network is checked field by field before it can reach the simulation.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "common/plumbing/expected.h"
#include "simulation/rollout_task.h"
#include "wire.pb.h"

namespace poet {

// A 64-bit content hash of θ (its values' bit patterns): equal parameters, equal hash.
uint64_t theta_hash(std::span<const double> theta);

wire::Task to_wire(const RolloutTask& task, uint64_t theta_hash);
wire::TaskResult to_wire(const RolloutResult& result);

// θ by hash, as a worker caches them.
using ThetaCache = std::unordered_map<uint64_t, std::shared_ptr<const std::vector<double>>>;

// Checks and adds a Theta message to the cache: kParamCount finite values whose hash is the one named. The
// error names the field ("thetas[0].values: 12 values, expected 2804").
std::optional<std::string> add_theta(const wire::Theta& message, ThetaCache& cache);

// The task a message describes, with its θ from the cache. Every field is checked (θ known, sign ±1, σ finite
// and ≥ 0, a valid course, push scale and max steps within the config's bounds, a known lidar rule).
Expected<RolloutTask> task_from_wire(const wire::Task& message, const ThetaCache& cache);

// A result message as the engine's value; finite return and steps ≥ 0, else an error.
Expected<RolloutResult> result_from_wire(const wire::TaskResult& message);
// A Result's rollout results when it holds exactly `count` of them and each is valid; nullopt otherwise.
std::optional<std::vector<RolloutResult>> results_from_wire(const wire::Result& message, size_t count);

}  // namespace poet
