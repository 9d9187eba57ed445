#pragma once
// What every command-line binary shares: the walker's options, --fingerprint, and what command_line.h holds (the
// exit codes, --version, and the parse that turns every bad command line into exit code 2).

#include <CLI/CLI.hpp>
#include <string>

#include "common/program/command_line.h"
#include "simulation/walker/walker_constants.h"
#include "simulation/walker/walker_env.h"

namespace poet {

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

}  // namespace poet
