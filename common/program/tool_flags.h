#pragma once
// What every command-line binary shares: the walker's options, --fingerprint, and the parse that turns every bad
// command line into exit code 2. Exit codes, as README.md says: 0 done, 1 runtime error, 2 bad command line,
// config or run directory, 130 interrupted.

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "simulation/walker/walker_constants.h"
#include "simulation/walker/walker_env.h"

namespace poet {

// Exit code of a process given a bad command line (never CLI11's own codes 101..).
inline constexpr int kExitUsage = 2;
// Exit code of a runtime error (a diverged run, a failed write, a failure reported by workers).
inline constexpr int kExitError = 1;
// poet-coordinator's exit code when it stopped at an iteration boundary, as asked (SIGUSR1, `poetctl stop
// --at-boundary`): the run is not finished, its checkpoint is the state, and a resume goes on from there.
inline constexpr int kExitStoppedAtBoundary = 3;

// The environment options of the tools that run episodes (poet-rollout, poet-eval).
struct WalkerFlags {
  double push_scale = walker::kDefaultPushScale;  // --push-scale, in [0, 1e4] N
  std::string lidar = "nearest";                  // --lidar: "nearest" or "first"
  int max_steps = walker::kDefaultTimeLimit;      // --max-steps, in [1, 1e6]; a rollout setting, not in options()

  WalkerOptions options() const;
};

// Adds --push-scale, --lidar and --max-steps bound to `flags`, which must outlive the parse.
void add_walker_flags(CLI::App& app, WalkerFlags& flags);

// Adds --fingerprint: prints build_fingerprint() to stdout, and parse_command_line() then returns 0.
void add_fingerprint_flag(CLI::App& app);

// Parses argv into `app`. nullopt: go on. 0: --help or --fingerprint printed what was asked, exit 0.
// kExitUsage (2): a bad command line, CLI11's message printed to stderr. Use: if (auto c = ...) return *c;
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv);

// A tool's exit code once its standard output is flushed: `code`, or kExitError (with a line on stderr prefixed
// `tool:`) when what it wrote did not all get there (a full disk, a failing device; not a pipe whose reader left),
// so that a truncated table or config never passes for a whole one.
// Use: int main(...) { return output_checked("poet-x", run(argc, argv)); }
int output_checked(const char* tool, int code);

}  // namespace poet
