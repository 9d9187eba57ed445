#pragma once
// A run directory's files by their relative paths, for comparing two runs byte for byte: all but run.lock (the
// owner's pid) and wall_times.csv (the machine's clock), which no two runs share.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>

#include "run_directory/files/wall_times.h"

namespace poet::testing {

inline std::map<std::string, std::string> run_files(const std::filesystem::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = std::filesystem::relative(entry.path(), dir).string();
    if (name == "run.lock" || name == kWallTimesFile) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    files[name] = std::string(std::istreambuf_iterator<char>(in), {});
  }
  return files;
}

}  // namespace poet::testing
