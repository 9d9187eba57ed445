// Tests the poet-coordinator process end to end: a run interrupted by a limit, by SIGINT or by SIGKILL and then
// resumed writes byte for byte the files of an uninterrupted run; bad input exits with a clear error.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr char kTinyConfig[] = R"(mode: POET
seed: 7
iterations: 6
checkpoint_interval: 1
es { perturbations: 4 }
walker { max_steps: 120 }
poet {
  mutation_interval: 2
  transfer_interval: 2
  repro_threshold: -1000
  mc_low: -1000
  mc_high: 1000
  max_children: 4
  max_admitted: 1
  active_cap: 3
}
)";

// The files a resumed run must reproduce exactly.
const char* const kRunFiles[] = {"checkpoint.pb", "events.jsonl", "pair_stats.csv"};

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

struct Outcome {
  int code = -1;  // the exit status, or 128 + signal
  std::string err;
};

int exit_code(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status); }

// A fresh directory per test; every child still running is killed and the directory removed, even on failure.
class CoordinatorProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("poet_coordinator_process_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
    config_ = root_ / "tiny.textproto";
    std::ofstream(config_) << kTinyConfig;
  }

  void TearDown() override {
    for (pid_t pid : children_) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
    fs::remove_all(root_);
  }

  // Starts poet-coordinator with args; its stdout and stderr go to files named after `name`.
  pid_t spawn(const std::vector<std::string>& args, const std::string& name) {
    std::vector<std::string> all = {POET_COORDINATOR_BIN};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string out = (root_ / (name + ".out")).string();
    const std::string err = (root_ / (name + ".err")).string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    EXPECT_EQ(rc, 0) << "posix_spawn " << argv[0];
    if (rc == 0) children_.push_back(pid);
    return rc == 0 ? pid : -1;
  }

  // Waits for a child (at most a few minutes: a hung child fails the test rather than hanging it).
  Outcome wait(pid_t pid, const std::string& name) {
    Outcome outcome;
    const auto deadline = std::chrono::steady_clock::now() + 300s;
    int status = 0;
    while (true) {
      const pid_t done = ::waitpid(pid, &status, WNOHANG);
      if (done == pid) break;
      if (done < 0 || std::chrono::steady_clock::now() > deadline) {
        ADD_FAILURE() << name << ": did not finish";
        return outcome;
      }
      std::this_thread::sleep_for(5ms);
    }
    std::erase(children_, pid);
    outcome.code = exit_code(status);
    outcome.err = read(root_ / (name + ".err"));
    return outcome;
  }

  Outcome run(const std::vector<std::string>& args, const std::string& name) {
    const pid_t pid = spawn(args, name);
    if (pid < 0) return {};
    return wait(pid, name);
  }

  // The uninterrupted run, in dir "A".
  fs::path reference_run() {
    const fs::path dir = root_ / "A";
    const Outcome outcome =
        run({"--config", config_.string(), "--run-dir", dir.string(), "--threads", "2", "--quiet"}, "A");
    EXPECT_EQ(outcome.code, 0) << outcome.err;
    return dir;
  }

  void expect_same_run_files(const fs::path& a, const fs::path& b) {
    for (const char* file : kRunFiles) {
      const std::string x = read(a / file);
      const std::string y = read(b / file);
      EXPECT_FALSE(x.empty()) << a / file;
      EXPECT_TRUE(x == y) << file << " differs: " << x.size() << " bytes in " << a << ", " << y.size() << " in " << b;
    }
  }

  // Starts a run in dir, and once it has checkpointed and logged an event, sends it `signal`.
  Outcome interrupt_run(const fs::path& dir, int signal, const std::string& name) {
    const pid_t pid = spawn(
        {"--config", config_.string(), "--run-dir", dir.string(), "--threads", "2", "--quiet", "--iterations", "6"},
        name);
    if (pid < 0) return {};
    const auto deadline = std::chrono::steady_clock::now() + 300s;
    while (std::chrono::steady_clock::now() < deadline) {
      if (fs::exists(dir / "checkpoint.pb") && contains(read(dir / "events.jsonl"), "\n")) break;
      int status = 0;
      if (::waitpid(pid, &status, WNOHANG) == pid) {  // finished before the signal: nothing to interrupt
        std::erase(children_, pid);
        return {exit_code(status), read(root_ / (name + ".err"))};
      }
      std::this_thread::sleep_for(1ms);
    }
    ::kill(pid, signal);
    return wait(pid, name);
  }

  fs::path root_;
  fs::path config_;
  std::vector<pid_t> children_;
};

TEST_F(CoordinatorProcessTest, ExtendedLimitContinuesExactly) {
  const fs::path a = reference_run();
  const fs::path b = root_ / "B";
  Outcome first = run(
      {"--config", config_.string(), "--run-dir", b.string(), "--threads", "2", "--quiet", "--iterations", "3"}, "B1");
  ASSERT_EQ(first.code, 0) << first.err;
  Outcome second = run({"--run-dir", b.string(), "--resume", "--iterations", "6", "--threads", "2", "--quiet"}, "B2");
  ASSERT_EQ(second.code, 0) << second.err;
  expect_same_run_files(a, b);
  EXPECT_EQ(read(a / "config.textproto"), read(b / "config.textproto"));
}

TEST_F(CoordinatorProcessTest, SigintCheckpointsAndResumesExactly) {
  const fs::path a = reference_run();
  const fs::path c = root_ / "C";
  const Outcome interrupted = interrupt_run(c, SIGINT, "C1");
  ASSERT_TRUE(interrupted.code == 130 || interrupted.code == 0) << interrupted.code << "\n" << interrupted.err;
  if (interrupted.code == 130) {
    EXPECT_TRUE(contains(interrupted.err, "interrupted at iteration")) << interrupted.err;
    EXPECT_TRUE(contains(interrupted.err, "--run-dir " + c.string() + " --resume")) << interrupted.err;
  }
  const Outcome resumed = run({"--run-dir", c.string(), "--resume", "--threads", "2", "--quiet"}, "C2");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  expect_same_run_files(a, c);
}

TEST_F(CoordinatorProcessTest, SigkillLosesNothingOfTheCheckpoint) {
  const fs::path a = reference_run();
  const fs::path c = root_ / "C";
  const Outcome killed = interrupt_run(c, SIGKILL, "C1");
  ASSERT_TRUE(killed.code == 128 + SIGKILL || killed.code == 0) << killed.code << "\n" << killed.err;
  const Outcome resumed = run({"--run-dir", c.string(), "--resume", "--threads", "1", "--quiet"}, "C2");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  expect_same_run_files(a, c);
}

TEST_F(CoordinatorProcessTest, BadConfigNamesTheField) {
  const fs::path bad = root_ / "bad.textproto";
  std::ofstream(bad) << "seed: 7\nbogus_field: 1\n";
  const Outcome outcome = run({"--config", bad.string(), "--run-dir", (root_ / "D").string(), "--quiet"}, "D");
  EXPECT_EQ(outcome.code, 2);
  EXPECT_TRUE(contains(outcome.err, "bogus_field")) << outcome.err;
  EXPECT_TRUE(contains(outcome.err, bad.string())) << outcome.err;
  EXPECT_FALSE(fs::exists(root_ / "D" / "checkpoint.pb"));

  std::ofstream(bad) << "es { init_sigma: -1 }\n";
  const Outcome invalid = run({"--config", bad.string(), "--run-dir", (root_ / "D").string(), "--quiet"}, "D2");
  EXPECT_EQ(invalid.code, 2);
  EXPECT_TRUE(contains(invalid.err, "es.init_sigma")) << invalid.err;
}

TEST_F(CoordinatorProcessTest, ResumeWithoutARunIsAClearError) {
  const fs::path empty = root_ / "E";
  fs::create_directories(empty);
  const Outcome outcome = run({"--run-dir", empty.string(), "--resume", "--quiet"}, "E");
  EXPECT_NE(outcome.code, 0);
  EXPECT_TRUE(contains(outcome.err, "checkpoint.pb")) << outcome.err;
  EXPECT_TRUE(contains(outcome.err, "no run to resume")) << outcome.err;

  const Outcome both = run({"--run-dir", empty.string(), "--resume", "--config", config_.string()}, "E2");
  EXPECT_EQ(both.code, 2) << both.err;
}

TEST_F(CoordinatorProcessTest, RefusesToStartOverAnExistingRun) {
  const fs::path a = reference_run();
  const std::string checkpoint = read(a / "checkpoint.pb");
  const Outcome outcome = run({"--config", config_.string(), "--run-dir", a.string(), "--quiet"}, "A2");
  EXPECT_EQ(outcome.code, 2);
  EXPECT_TRUE(contains(outcome.err, "already holds a run")) << outcome.err;
  EXPECT_TRUE(read(a / "checkpoint.pb") == checkpoint);
}

}  // namespace

std::string preset(const std::string& name) { return std::string(POET_SOURCE_DIR) + "/deploy/configs/" + name; }

// The README's main job, cut short: the quick preset admits children (iteration 6) and accepts a transfer
// (iteration 8) within its first nine iterations.
TEST_F(CoordinatorProcessTest, QuickPresetAdmitsChildrenAndAcceptsTransfers) {
  const fs::path dir = root_ / "quick";
  const Outcome outcome = run({"--config", preset("quick.textproto"), "--run-dir", dir.string(), "--threads", "2",
                               "--quiet", "--iterations", "9"},
                              "quick");
  ASSERT_EQ(outcome.code, 0) << outcome.err;
  const std::string events = read(dir / "events.jsonl");
  EXPECT_TRUE(contains(events, R"("event":"pair_created")")) << events;
  EXPECT_TRUE(contains(events, R"("event":"transfer")")) << events;
  EXPECT_TRUE(fs::exists(dir / "envs" / "pair-1.env.json"));
  EXPECT_TRUE(fs::exists(dir / "policies" / "pair-1.best.json"));
}

// Each control preset runs end to end as a mode of the same command.
TEST_F(CoordinatorProcessTest, ControlPresetsRun) {
  for (const std::string name : {"es_alone", "direct_path", "no_transfer"}) {
    const fs::path dir = root_ / name;
    const Outcome outcome = run({"--config", preset(name + ".textproto"), "--run-dir", dir.string(), "--threads",
                                 "2", "--quiet", "--iterations", "2"},
                                name);
    EXPECT_EQ(outcome.code, 0) << name << ": " << outcome.err;
    EXPECT_TRUE(contains(read(dir / "pair_stats.csv"), "\n1,0,")) << name;  // iteration 1 of pair 0 logged
  }
}
