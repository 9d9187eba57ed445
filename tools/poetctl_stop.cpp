#include "tools/poetctl_stop.h"

#include <unistd.h>

#include <cstdio>
#include <string>

#include "common/plumbing/host_name.h"
#include "common/plumbing/text_file.h"
#include "run_directory/files/boundary_stop.h"
#include "run_directory/files/run_directory.h"
#include "run_directory/files/run_lock.h"
#include "tools/poetctl_exit.h"

namespace poet {

int stop_at_boundary(const std::filesystem::path& run_dir) {
  if (run_dir.empty()) {
    std::fprintf(stderr, "poetctl stop: give the run directory\n");
    return kExitUnreachable;
  }
  const Expected<bool> has_config = path_exists(run_dir / kConfigFile);
  if (!has_config || !*has_config) {
    std::fprintf(stderr, "poetctl stop: %s holds no run (no %s)\n", run_dir.c_str(), kConfigFile);
    return kExitUnreachable;
  }
  const std::string who = "poetctl stop --at-boundary, pid " + std::to_string(::getpid()) + " on " + host_name();
  if (auto error = request_boundary_stop(run_dir, who)) {
    std::fprintf(stderr, "poetctl stop: %s: %s\n", (run_dir / kBoundaryStopFile).c_str(), error->c_str());
    return kExitUnreachable;
  }
  if (RunLock::held_by_another_process(run_dir)) {
    std::printf(
        "asked: the coordinator of %s stops once the iteration in flight is done and saved, exit code 3; go on "
        "with poet-coordinator --run-dir %s --resume\n",
        run_dir.c_str(), run_dir.c_str());
  } else {
    std::printf(
        "asked: no coordinator runs %s now; the next one to open it stops after one iteration (remove %s to take "
        "the request back)\n",
        run_dir.c_str(), (run_dir / kBoundaryStopFile).c_str());
  }
  return 0;
}

}  // namespace poet
