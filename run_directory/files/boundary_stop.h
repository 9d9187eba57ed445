#pragma once
// A request, left in a run directory, that the coordinator running it stop at its next iteration boundary: the
// iteration in flight finished, a checkpoint written, exit code kExitStoppedAtBoundary. `poetctl stop
// --at-boundary` writes it, so an operator on any machine that sees the directory (a shared file system) can ask;
// the coordinator looks for it after each iteration (SIGUSR1 asks the same of a process one can signal) and
// removes it when it stops for it, so that the next job of a chain runs on. The directory's permissions are who
// may ask.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"

namespace poet {

inline constexpr char kBoundaryStopFile[] = "stop-at-boundary";

// Writes the request (atomically); `who` goes into it for people. An error message, or nothing.
std::optional<std::string> request_boundary_stop(const std::filesystem::path& run_dir, std::string_view who);

// Whether a request is there; an error when that cannot be told (a directory that cannot be searched).
Expected<bool> boundary_stop_requested(const std::filesystem::path& run_dir);

// Removes the request once it is acted on. An error message, or nothing (also when there was none).
std::optional<std::string> clear_boundary_stop(const std::filesystem::path& run_dir);

}  // namespace poet
