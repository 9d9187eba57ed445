#pragma once
// Opening the run: a new one from its config (a directory that already holds a run of that config is resumed, as a
// restarted daemon runs the same command line) or the one a directory holds, with --iterations applied. Errors are
// logged; nullopt then.

#include <optional>
#include <utility>

#include "coordinator/daemon/daemon_options.h"
#include "engine/run_state.h"
#include "run_directory/files/run_directory.h"

namespace poet {

std::optional<std::pair<RunDirectory, RunState>> start_run(const DaemonOptions& options);
std::optional<std::pair<RunDirectory, RunState>> resume_run(const DaemonOptions& options);

}  // namespace poet
