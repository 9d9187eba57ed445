#pragma once
// poetctl (POETCTL_BIN, an integration tests' definition) as a child of a test, the way every test that asks a
// status socket through it runs it: default signal handling whatever the test process ignores or blocks, no
// $POET_STATUS but what the test sets, at most 30 s.

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "child_process.h"

namespace poet::testing {

// Runs poetctl with args in dir, stdout and stderr to dir/name.out and .err; extra_env is added to this process's
// environment (without its POET_STATUS).
inline ChildOutcome run_poetctl(Children& children, const std::filesystem::path& dir,
                                const std::vector<std::string>& args, const std::string& name,
                                const std::vector<std::string>& extra_env = {}) {
  std::vector<std::string> all = {POETCTL_BIN};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<std::string> environment = environment_without({"POET_STATUS"});
  environment.insert(environment.begin(), extra_env.begin(), extra_env.end());
  return children.run(std::move(all), dir / name, std::chrono::seconds(30),
                      {.default_signals = true, .environment = std::move(environment), .directory = dir});
}

}  // namespace poet::testing
