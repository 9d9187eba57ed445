#pragma once
// The fixture of the tests that run poet-coordinator with workers as real processes: a small POET config, a
// temporary root (removed afterwards), children started with their output in files and killed (with their own
// children, the local workers) at the end whatever happened, waits bounded in time, and the comparison of two
// run directories byte for byte. Directories and processes come from tests/support.

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"
#include "scratch_dir.h"

namespace poet::testing {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr char kConfig[] = R"(mode: POET
seed: 7
iterations: 6
es { perturbations: 4 }
walker { max_steps: 120 }
poet { mutation_interval: 2 transfer_interval: 2 repro_threshold: -1000 mc_low: -1000 mc_high: 1000
       max_children: 4 max_admitted: 1 active_cap: 3 }
)";

const char* const kRunFiles[] = {"checkpoint.pb", "events.jsonl", "pair_stats.csv", "annecs.csv"};

inline std::string read(const fs::path& path) { return read_file(path); }

class CoordinatorRunTest : public ::testing::Test {
 protected:
  void SetUp() override { std::ofstream(config_) << kConfig; }

  pid_t spawn(const char* binary, std::vector<std::string> args, const std::string& name,
              const ChildOptions& options = {}) {
    args.insert(args.begin(), binary);
    return children_.start(std::move(args), root_ / name, options);
  }

  pid_t coordinator(const fs::path& dir, std::vector<std::string> extra, const std::string& name,
                    const ChildOptions& options = {}) {
    std::vector<std::string> args = {"--config",         config_.string(), "--run-dir",     dir.string(), "--quiet",
                                     "--status-address", "127.0.0.1:0",    "--liveness-ms", "1000"};
    args.insert(args.end(), extra.begin(), extra.end());
    return spawn(POET_COORDINATOR_BIN, args, name, options);
  }

  // Waits (at most two minutes) for the process to end; its exit code, or -1 when it did not.
  int wait(pid_t pid) {
    const std::optional<int> code = children_.wait(pid, 120s);
    if (!code) ADD_FAILURE() << "process " << pid << " did not end";
    return code.value_or(-1);
  }

  // The first match of `pattern` (group 1) in the process's stderr, once it appears (at most 30 s).
  std::string await_log(const std::string& name, const std::string& pattern) {
    const std::regex re(pattern);
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    while (std::chrono::steady_clock::now() < deadline) {
      std::smatch m;
      const std::string err = read(root_ / (name + ".err"));
      if (std::regex_search(err, m, re)) return m[1];
      std::this_thread::sleep_for(10ms);
    }
    ADD_FAILURE() << name << ": no log line matching " << pattern;
    return "";
  }

  fs::path threads_run() {
    const fs::path dir = root_ / "threads";
    const pid_t pid = coordinator(dir, {"--threads", "2"}, "threads");
    EXPECT_EQ(wait(pid), 0) << read(root_ / "threads.err");
    return dir;
  }

  void expect_same_run(const fs::path& a, const fs::path& b) {
    for (const char* file : kRunFiles) {
      const std::string x = read(a / file);
      EXPECT_FALSE(x.empty()) << a / file;
      EXPECT_TRUE(x == read(b / file)) << file << " differs between " << a << " and " << b;
    }
  }

  // the children go first (killed with their local workers), the directory after them
  ScratchDir scratch_{"poet_run_test"};
  fs::path root_ = scratch_.path();
  fs::path config_ = root_ / "tiny.textproto";
  Children children_;
};

// The config with one line replaced.
inline std::string config_with(const std::string& from, const std::string& to) {
  std::string text = kConfig;
  return text.replace(text.find(from), from.size(), to);
}

}  // namespace poet::testing
