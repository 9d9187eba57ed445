#pragma once
// poetctl stop --at-boundary: asks the coordinator of a run directory to stop at its next iteration boundary with a
// checkpoint (run_directory/files/boundary_stop.h), through the directory itself, so that it works from any
// machine that sees it (a shared file system) and no socket takes orders.

#include <filesystem>

namespace poet {

// Leaves the request in RUN_DIR (which must hold a run) and says what happens next. Returns the exit code: 0, or
// 1 naming what failed.
int stop_at_boundary(const std::filesystem::path& run_dir);

}  // namespace poet
