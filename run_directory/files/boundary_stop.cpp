#include "run_directory/files/boundary_stop.h"

#include <system_error>

#include "common/plumbing/text_file.h"

namespace poet {

std::optional<std::string> request_boundary_stop(const std::filesystem::path& run_dir, std::string_view who) {
  const std::string text = "stop at the next iteration boundary, asked by " + std::string(who) + "\n";
  return write_file_atomically(run_dir / kBoundaryStopFile, text);
}

Expected<bool> boundary_stop_requested(const std::filesystem::path& run_dir) {
  return path_exists(run_dir / kBoundaryStopFile);
}

std::optional<std::string> clear_boundary_stop(const std::filesystem::path& run_dir) {
  std::error_code error;
  std::filesystem::remove(run_dir / kBoundaryStopFile, error);
  if (error) return error.message();
  sync_directory(run_dir);
  return std::nullopt;
}

}  // namespace poet
