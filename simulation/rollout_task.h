#pragma once
// A rollout as a unit of work: the policy (shared θ plus an optional seeded perturbation), the course and the
// episode settings. Tasks carry seeds, not noise, so a task is small and any process rebuilds the same episode.
// Workers and the in-process evaluator both run tasks with run_task(); there is one simulation path.

#include <cstdint>
#include <memory>
#include <optional>
#include <stop_token>
#include <vector>

#include "simulation/envgen/env_encoding.h"
#include "simulation/rollout.h"
#include "simulation/walker/walker_env.h"

namespace poet {

// θ + sign·σ·ε(key), ε rebuilt by fill_perturbation (es/perturbation.h).
struct Perturbation {
  uint64_t key = 0;
  int sign = 1;  // +1 or −1 (mirrored sampling)
  double sigma = 0;
};

struct RolloutTask {
  std::shared_ptr<const std::vector<double>> theta;  // kParamCount values; shared by the tasks of one batch
  std::optional<Perturbation> perturbation;
  EnvDef env;
  WalkerOptions walker;
  int max_steps = walker::kDefaultTimeLimit;
};

// Runs the task's episode (no trajectory). Deterministic in the task's contents. Throws std::invalid_argument
// for a task that cannot run (no θ, wrong size, non-finite parameters, a sign other than ±1, an invalid course);
// tasks from the network are validated before they get here. A stop request on `stop` cuts the episode short
// (result.stopped).
RolloutResult run_task(const RolloutTask& task, std::stop_token stop = {});

}  // namespace poet
