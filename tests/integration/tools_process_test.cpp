// Tests the command-line tools as real processes: every bad command line exits 2, --fingerprint prints the same
// text in every tool (and in this test binary, built with the same flags), poet-rollout names the policy it runs.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "build_fingerprint.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

struct Tool {
  const char* name;
  const char* path;
};

// Every binary of the project, poet-coordinator and poet-worker included: the same rules for all.
const Tool kTools[] = {{"poet-coordinator", POET_COORDINATOR_BIN},
                       {"poet-rollout", POET_ROLLOUT_BIN},
                       {"poet-eval", POET_EVAL_BIN},
                       {"poet-fidelity", POET_FIDELITY_BIN},
                       {"poet-lineage", POET_LINEAGE_BIN},
                       {"poet-worker", POET_WORKER_BIN},
                       {"poetctl", POETCTL_BIN}};

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

struct Outcome {
  int code = -1;  // the exit status, or 128 + signal; -1 when it could not be started or did not finish
  std::string out, err;
};

// A fresh working directory per test, where the tools run and their output goes; TearDown kills any child still
// running and removes the directory, even when the test failed.
class ToolsProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() / ("poet_tools_process_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }

  void TearDown() override {
    for (pid_t pid : children_) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
    fs::remove_all(root_);
  }

  // Runs `path args...` in root_, stdout and stderr to root_/name.out and .err, for at most a minute.
  Outcome run(const char* path, const std::vector<std::string>& args, const std::string& name) {
    std::vector<std::string> all = {path};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    const fs::path out = root_ / (name + ".out"), err = root_ / (name + ".err");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addchdir_np(&actions, root_.c_str());
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
      ADD_FAILURE() << "posix_spawn " << path << ": " << std::strerror(rc);
      return {};
    }
    children_.push_back(pid);

    // a hung tool fails the test rather than hanging it
    const auto deadline = std::chrono::steady_clock::now() + 60s;
    int status = 0;
    while (::waitpid(pid, &status, WNOHANG) != pid) {
      if (std::chrono::steady_clock::now() > deadline) {
        ADD_FAILURE() << name << ": did not finish within 60 s";
        return {};
      }
      std::this_thread::sleep_for(5ms);
    }
    std::erase(children_, pid);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), read(out), read(err)};
  }

  fs::path root_;
  std::vector<pid_t> children_;
};

TEST_F(ToolsProcessTest, UnknownFlagExitsTwo) {
  for (const Tool& tool : kTools) {
    const Outcome o = run(tool.path, {"--no-such-flag"}, tool.name);
    EXPECT_EQ(o.code, 2) << tool.name << "\n" << o.err;
    EXPECT_FALSE(o.err.empty()) << tool.name;
  }
}

TEST_F(ToolsProcessTest, BadValueExitsTwo) {
  const std::vector<std::pair<const char*, std::vector<std::string>>> cases = {
      {POET_ROLLOUT_BIN, {"--lidar", "sideways"}},
      {POET_ROLLOUT_BIN, {"--push-scale", "-1"}},
      {POET_ROLLOUT_BIN, {"--max-steps", "0"}},
      {POET_EVAL_BIN, {"--policy", "none.json", "--lidar", "sideways"}},
      {POET_EVAL_BIN, {"--policy", "none.json", "--push-scale", "-1"}},
      {POET_FIDELITY_BIN, {"--threads", "0"}},
      {POET_LINEAGE_BIN, {"--run-dir", "none", "--pair", "seventeen"}},
      {POET_COORDINATOR_BIN, {"--run-dir", "none", "--threads", "0"}},
      {POET_COORDINATOR_BIN, {"--run-dir", "none", "--log-level", "loud"}},
  };
  int n = 0;
  for (const auto& [path, args] : cases) {
    const Outcome o = run(path, args, "case" + std::to_string(n++));
    EXPECT_EQ(o.code, 2) << path << " " << args.back() << "\n" << o.err;
    EXPECT_TRUE(contains(o.err, args.back())) << path << "\n" << o.err;  // CLI11 names the bad value
  }
}

TEST_F(ToolsProcessTest, FingerprintIsTheSameInEveryTool) {
  const std::string expected = poet::build_fingerprint();
  ASSERT_TRUE(contains(expected, "digest:"));
  for (const Tool& tool : kTools) {
    const Outcome o = run(tool.path, {"--fingerprint"}, tool.name);
    EXPECT_EQ(o.code, 0) << tool.name << "\n" << o.err;
    EXPECT_EQ(o.out, expected) << tool.name;
    EXPECT_EQ(o.err, "") << tool.name;
  }
}

TEST_F(ToolsProcessTest, RolloutWithoutPolicySaysItRunsRandomTheta) {
  const Outcome o = run(POET_ROLLOUT_BIN, {"--max-steps", "50", "--picture", ""}, "rollout");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(contains(o.out, "policy: random θ")) << o.out;
  EXPECT_TRUE(contains(o.out, "no --policy given")) << o.out;
  EXPECT_TRUE(contains(o.out, "return ")) << o.out;
  // with --picture '' nothing is written: the directory holds only the captured output
  for (const auto& entry : fs::directory_iterator(root_)) {
    const std::string file = entry.path().filename().string();
    EXPECT_TRUE(file == "rollout.out" || file == "rollout.err") << file;
  }
}

}  // namespace
