#pragma once
// A command line with what --help, --help-json and the command-line reference show: a required option, a captured
// default, a default stated in words, a flag that excludes another, a hidden option, and a subcommand with a
// positional and an option of its own.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

namespace poet::testing {

struct SampleCommandLine {
  CLI::App app{"A test tool | with a bar"};
  std::string policy;
  int threads = 4;
  int workers = 0;
  bool quiet = false;
  bool loud = false;
  int hidden = 0;
  int pair = 0;
  int64_t since = 0;

  SampleCommandLine() {
    app.add_option("--policy", policy, "Policy file")->required();
    app.add_option("--threads", threads, "Threads")->capture_default_str()->check(CLI::Range(1, 64));
    app.add_option("--workers", workers, "Workers (default: one per core)");
    auto* loud_flag = app.add_flag("--loud", loud, "Say more");
    app.add_flag("--quiet", quiet, "Say less")->excludes(loud_flag);
    app.add_option("--hidden", hidden, "For tools")->group("");
    CLI::App* sub = app.add_subcommand("pair", "One pair");
    sub->add_option("id", pair, "The pair's id")->required();
    sub->add_option("--since", since, "The first line (0-based; default 0)");
  }
};

}  // namespace poet::testing
