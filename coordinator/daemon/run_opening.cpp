#include "coordinator/daemon/run_opening.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <string>
#include <vector>

#include "common/formats/policy/policy_file.h"
#include "engine/engine.h"
#include "run_directory/config/run_config.h"
#include "run_directory/files/checkpoint_file.h"

namespace poet {
namespace {

// A resumed run: the checkpoint's state, with --iterations applied (and recorded in the directory).
std::optional<std::pair<RunDirectory, RunState>> continue_run(Expected<std::pair<RunDirectory, RunState>> resumed,
                                                              const DaemonOptions& options,
                                                              std::optional<int> iterations) {
  if (!resumed) {
    spdlog::error("{}", resumed.error());
    return std::nullopt;
  }
  auto& [dir, state] = *resumed;
  if (iterations && (!dir.config().has_iterations() || dir.config().iterations() != *iterations)) {
    pb::RunConfig config = dir.config();
    config.set_iterations(*iterations);
    if (auto error = validate(config)) {
      spdlog::error("--iterations: {}", *error);
      return std::nullopt;
    }
    state.settings = run_settings(config);
    std::optional<std::string> error = dir.write_config(config);
    if (!error) error = dir.save(state);
    if (error) {
      spdlog::error("{}", *error);
      return std::nullopt;
    }
  }
  spdlog::info("resumed {} at iteration {} of {}", options.run_dir, state.next_iteration, state.settings.iterations);
  return std::move(*resumed);
}

// The configs of one run: equal but for the iteration limit, which a resume may change.
bool same_run(pb::RunConfig a, pb::RunConfig b) {
  a.clear_iterations();
  b.clear_iterations();
  return a.SerializeAsString() == b.SerializeAsString();
}

}  // namespace

// A new run: the config (with --iterations applied), a fresh directory and its first checkpoint. A directory
// that already holds a run of the same config is resumed (a restarted daemon runs the same command line).
std::optional<std::pair<RunDirectory, RunState>> start_run(const DaemonOptions& options) {
  Expected<pb::RunConfig> config = load_run_config(options.config_path);
  if (!config) {
    spdlog::error("{}", config.error());
    return std::nullopt;
  }
  if (options.iterations) {
    config->set_iterations(*options.iterations);
    if (auto error = validate(*config)) {
      spdlog::error("--iterations: {}", *error);
      return std::nullopt;
    }
  }
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::path(options.run_dir) / kCheckpointFile, ec)) {
    Expected<std::pair<RunDirectory, RunState>> resumed = RunDirectory::resume(options.run_dir);
    if (resumed && !same_run(resumed->first.config(), *config)) {
      spdlog::error("{} already holds a run of another config; resume it with --resume, or choose another directory",
                    options.run_dir);
      return std::nullopt;
    }
    return continue_run(std::move(resumed), options, config->iterations());
  }
  std::optional<std::vector<double>> start_theta;
  if (!options.start_from.empty()) {
    Expected<PolicyFile> policy = load_policy(options.start_from);
    if (!policy) {
      spdlog::error("--start-from {}", policy.error());
      return std::nullopt;
    }
    spdlog::info("the first pair starts from {}{}", options.start_from,
                 policy->score ? fmt::format(" (score {:.1f} there)", *policy->score) : "");
    start_theta = std::move(policy->params);
  }
  Expected<RunDirectory> dir = RunDirectory::create(options.run_dir, *config);
  if (!dir) {
    spdlog::error("{}", dir.error());
    return std::nullopt;
  }
  RunState state = initial_state(run_settings(*config), std::move(start_theta));
  if (auto error = dir->save(state)) {
    spdlog::error("{}", *error);
    return std::nullopt;
  }
  spdlog::info("new run in {}: mode {}, seed {}, {} iterations", options.run_dir,
               pb::RunConfig::Mode_Name(config->mode()), config->seed(), config->iterations());
  return std::pair<RunDirectory, RunState>(std::move(*dir), std::move(state));
}

std::optional<std::pair<RunDirectory, RunState>> resume_run(const DaemonOptions& options) {
  return continue_run(RunDirectory::resume(options.run_dir), options, options.iterations);
}

}  // namespace poet
