// Tests the poet-coordinator process end to end: a run interrupted by a limit, by SIGINT or by SIGKILL and then
// resumed writes byte for byte the files of an uninterrupted run; a stop abandons the iteration in flight at once;
// one process owns a run directory; bad input (configs, corrupt checkpoints) exits with a clear error, and a
// diverging run stops saying that a resume would repeat it; a run packed and restored elsewhere goes on exactly.
// Tests that interrupt a run assert that the signal arrived before the run's end.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"
#include "common/formats/policy/policy_file.h"
#include "run_directory/files/checkpoint_file.h"
#include "run_directory/files/run_pack.h"
#include "scratch_dir.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

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
const char* const kRunFiles[] = {"checkpoint.pb", "events.jsonl", "pair_stats.csv", "annecs.csv"};

std::string read(const fs::path& path) { return poet::testing::read_file(path); }

using poet::testing::contains;

struct Outcome {
  int code = -1;  // the exit status, or 128 + signal
  std::string err;
  double seconds = 0;  // from the start of the wait
};

// The iteration a run directory's checkpoint resumes at, or -1 when there is no readable checkpoint.
int checkpoint_iteration(const fs::path& dir) {
  if (!fs::exists(dir / "checkpoint.pb")) return -1;
  const auto checkpoint = poet::read_checkpoint_file(dir / "checkpoint.pb");
  return checkpoint ? checkpoint->next_iteration() : -1;
}

std::string preset(const std::string& name) { return std::string(POET_SOURCE_DIR) + "/deploy/configs/" + name; }

// Long enough that no test run reaches it: a run given this limit is still running when it is signalled.
constexpr char kEndless[] = "100000";

// A fresh directory per test; every child still running is killed and the directory removed, even on failure.
class CoordinatorProcessTest : public ::testing::Test {
 protected:
  void SetUp() override { std::ofstream(config_) << kTinyConfig; }

  // Starts poet-coordinator with args; its stdout and stderr go to files named after `name`. With blocked_signal,
  // the child starts with that signal blocked (as a parent's mask is inherited), so one sent at once is pending
  // when the coordinator starts.
  pid_t spawn(const std::vector<std::string>& args, const std::string& name, int blocked_signal = 0) {
    std::vector<std::string> all = {POET_COORDINATOR_BIN};
    all.insert(all.end(), args.begin(), args.end());
    return children_.start(std::move(all), root_ / name, {.blocked_signal = blocked_signal});
  }

  // Waits for a child (at most a few minutes: a hung child fails the test rather than hanging it).
  Outcome wait(pid_t pid, const std::string& name) {
    const auto started = std::chrono::steady_clock::now();
    const std::optional<int> code = children_.wait(pid, 300s);
    if (!code) {
      ADD_FAILURE() << name << ": did not finish";
      return {};
    }
    return {*code, read(root_ / (name + ".err")),
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()};
  }

  Outcome run(const std::vector<std::string>& args, const std::string& name) {
    const pid_t pid = spawn(args, name);
    if (pid < 0) return {};
    return wait(pid, name);
  }

  // The run in dir resumed on two threads up to the reference run's end (iteration 6).
  Outcome resume(const fs::path& dir, const std::string& name) {
    return run({"--run-dir", dir.string(), "--resume", "--threads", "2", "--quiet", "--iterations", "6"}, name);
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

  // Starts a run in dir with a limit it cannot reach; once it has checkpointed iteration `after`, returns its pid
  // (or -1, failing the test, when it ended or never got there).
  pid_t start_endless_run(const fs::path& dir, int after, const std::string& name, const fs::path& config) {
    const pid_t pid = spawn(
        {"--config", config.string(), "--run-dir", dir.string(), "--threads", "2", "--quiet", "--iterations", kEndless},
        name);
    if (pid < 0) return -1;
    const auto deadline = std::chrono::steady_clock::now() + 300s;
    while (std::chrono::steady_clock::now() < deadline) {
      if (checkpoint_iteration(dir) >= after) return pid;
      if (const std::optional<int> code = children_.ended(pid)) {
        ADD_FAILURE() << name << " ended (" << *code << ") before the signal:\n" << read(root_ / (name + ".err"));
        return -1;
      }
      std::this_thread::sleep_for(1ms);
    }
    ADD_FAILURE() << name << ": no checkpoint of iteration " << after << " in time";
    return -1;
  }

  // Sends `signal` to a run in the middle of its course and waits for it; the run cannot have finished.
  Outcome interrupt_run(const fs::path& dir, int signal, const std::string& name) {
    const pid_t pid = start_endless_run(dir, 2, name, config_);
    if (pid < 0) return {};
    EXPECT_EQ(::kill(pid, signal), 0);
    return wait(pid, name);
  }

  // the children go first, the directory after them
  poet::testing::ScratchDir scratch_{"poet_coordinator_process_test"};
  fs::path root_ = scratch_.path();
  fs::path config_ = root_ / "tiny.textproto";
  poet::testing::Children children_;
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

TEST_F(CoordinatorProcessTest, SigintStopsAndTheResumeRepeatsTheIterationExactly) {
  const fs::path a = reference_run();
  const fs::path c = root_ / "C";
  const Outcome interrupted = interrupt_run(c, SIGINT, "C1");
  ASSERT_EQ(interrupted.code, 130) << interrupted.err;
  EXPECT_TRUE(contains(interrupted.err, "--run-dir " + c.string() + " --resume")) << interrupted.err;
  const int stopped_at = checkpoint_iteration(c);
  ASSERT_GE(stopped_at, 2);
  ASSERT_LT(stopped_at, 6) << "the signal came after the reference run's end: nothing left to compare";
  const Outcome resumed = resume(c, "C2");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  expect_same_run_files(a, c);
}

TEST_F(CoordinatorProcessTest, SigkillLosesNothingOfTheCheckpointAndLeavesNoLockBehind) {
  const fs::path a = reference_run();
  const fs::path c = root_ / "C";
  const Outcome killed = interrupt_run(c, SIGKILL, "C1");
  ASSERT_EQ(killed.code, 128 + SIGKILL) << killed.err;
  const int killed_at = checkpoint_iteration(c);
  ASSERT_GE(killed_at, 2);
  ASSERT_LT(killed_at, 6) << "the signal came after the reference run's end: nothing left to compare";
  ASSERT_TRUE(fs::exists(c / "run.lock"));  // the dead process's lock file stays, and must not block
  const Outcome resumed =
      run({"--run-dir", c.string(), "--resume", "--threads", "1", "--quiet", "--iterations", "6"}, "C2");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  expect_same_run_files(a, c);
}

// A run packed while it goes on (poetctl pack), stopped, and restored elsewhere with --from-pack ends with the files
// of a run that never moved; a damaged pack and a destination that holds a run are refused, changing nothing.
TEST_F(CoordinatorProcessTest, APackedRunGoesOnElsewhereAsIfItNeverMoved) {
  const fs::path a = reference_run();
  const fs::path b = root_ / "B";
  const fs::path pack = root_ / "B.pack";
  const pid_t pid = start_endless_run(b, 2, "B1", config_);
  ASSERT_GT(pid, 0);
  const pid_t packer = children_.start({POETCTL_BIN, "pack", b.string(), pack.string()}, root_ / "pack");
  const std::optional<int> packed = children_.wait(packer, 60s);
  ASSERT_EQ(packed, 0) << read(root_ / "pack.err");
  EXPECT_TRUE(contains(read(root_ / "pack.out"), "verified")) << read(root_ / "pack.out");
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  ASSERT_EQ(wait(pid, "B1").code, 130);
  const poet::Expected<poet::PackSummary> summary = poet::decode_pack(read(pack));
  ASSERT_TRUE(summary) << summary.error();
  ASSERT_GE(summary->next_iteration, 2);
  ASSERT_LT(summary->next_iteration, 6) << "packed after the reference run's end: nothing left to compare";

  // unpacked without running: the run as it was stopped, with the files derived from its checkpoint
  const fs::path u = root_ / "U";
  const pid_t unpacker = children_.start({POETCTL_BIN, "unpack", pack.string(), u.string()}, root_ / "unpack");
  ASSERT_EQ(children_.wait(unpacker, 60s), 0) << read(root_ / "unpack.err");
  for (const poet::PackEntry& entry : summary->entries) EXPECT_EQ(read(u / entry.name), entry.content) << entry.name;
  for (const char* file : {"annecs.csv", "envs/pair-0.env.json", "policies/pair-0.best.json"})
    EXPECT_TRUE(fs::exists(u / file)) << file;
  EXPECT_EQ(read(u / "config.textproto"), read(b / "config.textproto"));

  // restored into a directory that does not exist yet, under a parent that does not either
  const fs::path c = root_ / "elsewhere" / "C";
  const Outcome moved = run({"--run-dir", c.string(), "--resume", "--from-pack", pack.string(), "--threads", "1",
                             "--quiet", "--iterations", "6"},
                            "C");
  ASSERT_EQ(moved.code, 0) << moved.err;
  EXPECT_TRUE(contains(moved.err, "restored the run packed in")) << moved.err;
  expect_same_run_files(a, c);
  for (const char* file : {"config.textproto", "envs/pair-1.env.json", "policies/pair-0.best.json"})
    EXPECT_EQ(read(a / file), read(c / file)) << file;

  // into a directory that holds a run: refused, the run untouched
  const std::string before = read(c / "checkpoint.pb");
  const Outcome over = run({"--run-dir", c.string(), "--resume", "--from-pack", pack.string(), "--quiet"}, "over");
  EXPECT_EQ(over.code, 2) << over.err;
  EXPECT_TRUE(contains(over.err, "never overwritten")) << over.err;
  EXPECT_EQ(read(c / "checkpoint.pb"), before);
  // a damaged pack: refused with the reason, nothing made
  std::string damaged = read(pack);
  damaged[damaged.size() / 2] ^= 0x20;
  std::ofstream(pack, std::ios::binary | std::ios::trunc) << damaged;
  const Outcome bad = run({"--run-dir", (root_ / "D").string(), "--resume", "--from-pack", pack.string()}, "bad");
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_TRUE(contains(bad.err, "CRC-32 mismatch")) << bad.err;
  EXPECT_FALSE(fs::exists(root_ / "D"));
  // --from-pack is a resume's
  const Outcome without_resume =
      run({"--config", config_.string(), "--run-dir", (root_ / "E").string(), "--from-pack", pack.string()}, "E");
  EXPECT_EQ(without_resume.code, 2) << without_resume.err;
}

// The iteration in flight is abandoned at once, not finished: iteration 0 of this run takes some 25 s on two
// threads (4096 episodes of about 120 steps; the zero policy falls after about 120 steps).
TEST_F(CoordinatorProcessTest, SigtermAbandonsALongIterationAtOnce) {
  const fs::path slow = root_ / "slow.textproto";
  std::ofstream(slow)
      << "mode: POET\nseed: 3\ninit_zero: true\nes { perturbations: 2048 init_sigma: 0.0001 sigma_floor: 0 }\n";
  const fs::path dir = root_ / "S";
  const pid_t pid = start_endless_run(dir, 0, "S", slow);
  ASSERT_GT(pid, 0);
  std::this_thread::sleep_for(1500ms);  // well into iteration 0
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  const Outcome stopped = wait(pid, "S");
  EXPECT_EQ(stopped.code, 143) << "128 + SIGTERM: " << stopped.err;
  EXPECT_LT(stopped.seconds, 5.0) << "the stop waited for the iteration";
  EXPECT_TRUE(contains(stopped.err, "stopped during iteration 0")) << stopped.err;
  EXPECT_TRUE(contains(stopped.err, "checkpoint at iteration 0")) << stopped.err;
  EXPECT_EQ(checkpoint_iteration(dir), 0);
  EXPECT_EQ(read(dir / "events.jsonl"), "");
}

// SIGUSR1 (SLURM's warning before a time limit) lets the iteration in flight finish, saves it and exits 3; the run
// resumed from there ends in the files of a run never stopped.
TEST_F(CoordinatorProcessTest, Sigusr1StopsAtTheNextBoundaryAndTheResumeEndsAsAStraightRun) {
  const fs::path a = reference_run();
  const fs::path c = root_ / "C";
  const pid_t pid = start_endless_run(c, 2, "C1", config_);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(::kill(pid, SIGUSR1), 0);
  const Outcome stopped = wait(pid, "C1");
  ASSERT_EQ(stopped.code, 3) << stopped.err;
  EXPECT_TRUE(contains(stopped.err, "stopped at the boundary of iterations")) << stopped.err;
  EXPECT_TRUE(contains(stopped.err, "as asked (SIGUSR1)")) << stopped.err;
  const int stopped_at = checkpoint_iteration(c);
  ASSERT_GE(stopped_at, 2);
  ASSERT_LT(stopped_at, 6) << "the signal came after the reference run's end: nothing left to compare";
  EXPECT_TRUE(contains(stopped.err, "checkpoint at iteration " + std::to_string(stopped_at))) << stopped.err;
  const Outcome resumed = resume(c, "C2");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  expect_same_run_files(a, c);
}

// `poetctl stop --at-boundary` asks through the run directory: the coordinator running it stops at its next
// boundary and removes the request; asked while none runs, the next to open the run stops after one iteration.
TEST_F(CoordinatorProcessTest, PoetctlStopAtBoundaryAsksThroughTheRunDirectory) {
  const fs::path a = reference_run();
  const fs::path c = root_ / "C";
  auto poetctl_stop = [&](const fs::path& dir, const std::string& name) {
    const pid_t pid = children_.start({POETCTL_BIN, "stop", dir.string(), "--at-boundary"}, root_ / name);
    return children_.wait(pid, 60s).value_or(-1);
  };
  const pid_t pid = start_endless_run(c, 2, "C1", config_);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(poetctl_stop(c, "ask1"), 0) << read(root_ / "ask1.err");
  EXPECT_TRUE(contains(read(root_ / "ask1.out"), "stops once the iteration in flight is done"))
      << read(root_ / "ask1.out");
  const Outcome stopped = wait(pid, "C1");
  ASSERT_EQ(stopped.code, 3) << stopped.err;
  EXPECT_TRUE(contains(stopped.err, "as asked (" + (c / "stop-at-boundary").string() + ")")) << stopped.err;
  EXPECT_FALSE(fs::exists(c / "stop-at-boundary")) << "the request stays after it was acted on";
  const int stopped_at = checkpoint_iteration(c);
  ASSERT_LT(stopped_at, 5) << "the request came too late to see a stop between two resumes";

  ASSERT_EQ(poetctl_stop(c, "ask2"), 0) << read(root_ / "ask2.err");
  EXPECT_TRUE(contains(read(root_ / "ask2.out"), "no coordinator runs")) << read(root_ / "ask2.out");
  const Outcome one_more = resume(c, "C2");
  ASSERT_EQ(one_more.code, 3) << one_more.err;
  EXPECT_EQ(checkpoint_iteration(c), stopped_at + 1);
  const Outcome resumed = resume(c, "C3");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  expect_same_run_files(a, c);

  EXPECT_EQ(poetctl_stop(root_ / "nothing", "ask3"), 1);
  EXPECT_TRUE(contains(read(root_ / "ask3.err"), "holds no run")) << read(root_ / "ask3.err");
}

// A stop at the boundary waits for the iteration in flight, however long; SIGTERM after it keeps its meaning and
// abandons the iteration at once.
TEST_F(CoordinatorProcessTest, Sigusr1WaitsForALongIterationAndSigtermStillAbandonsIt) {
  const fs::path slow = root_ / "slow.textproto";
  std::ofstream(slow)
      << "mode: POET\nseed: 3\ninit_zero: true\nes { perturbations: 2048 init_sigma: 0.0001 sigma_floor: 0 }\n";
  const fs::path dir = root_ / "S";
  const pid_t pid = start_endless_run(dir, 0, "S", slow);
  ASSERT_GT(pid, 0);
  std::this_thread::sleep_for(1500ms);  // well into iteration 0
  ASSERT_EQ(::kill(pid, SIGUSR1), 0);
  std::this_thread::sleep_for(1000ms);
  ASSERT_EQ(children_.ended(pid), std::nullopt) << "SIGUSR1 ended the process: " << read(root_ / "S.err");
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  const Outcome stopped = wait(pid, "S");
  EXPECT_EQ(stopped.code, 143) << stopped.err;
  EXPECT_LT(stopped.seconds, 5.0) << "the stop waited for the iteration";
  EXPECT_TRUE(contains(stopped.err, "stopped during iteration 0")) << stopped.err;
  EXPECT_EQ(checkpoint_iteration(dir), 0);
}

// A signal while the process starts (here pending before its first instruction) ends it at once with 128 + its
// number.
TEST_F(CoordinatorProcessTest, ASignalDuringStartUpExitsAtOnce) {
  const pid_t pid =
      spawn({"--config", config_.string(), "--run-dir", (root_ / "U").string(), "--quiet", "--iterations", kEndless},
            "U", SIGTERM);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  const Outcome outcome = wait(pid, "U");
  EXPECT_EQ(outcome.code, 143) << outcome.err;
  EXPECT_LT(outcome.seconds, 5.0);
  EXPECT_LE(checkpoint_iteration(root_ / "U"), 0);  // no iteration ran
}

TEST_F(CoordinatorProcessTest, ASecondCoordinatorOnTheSameDirectoryIsRefused) {
  const fs::path a = reference_run();
  const fs::path dir = root_ / "L";
  const pid_t owner = start_endless_run(dir, 1, "L1", config_);
  ASSERT_GT(owner, 0);
  const std::string holder = "is in use by another process (pid " + std::to_string(owner) + ")";
  const Outcome second = run({"--config", config_.string(), "--run-dir", dir.string(), "--quiet"}, "L2");
  EXPECT_EQ(second.code, 2) << second.err;
  EXPECT_TRUE(contains(second.err, holder)) << second.err;
  const Outcome resume = run({"--run-dir", dir.string(), "--resume", "--quiet"}, "L3");
  EXPECT_EQ(resume.code, 2) << resume.err;
  EXPECT_TRUE(contains(resume.err, holder)) << resume.err;
  ASSERT_EQ(::kill(owner, SIGINT), 0);
  ASSERT_EQ(wait(owner, "L1").code, 130);
  ASSERT_LT(checkpoint_iteration(dir), 6);
  // the refused processes changed nothing: the owner's run continues into the reference run's files
  const Outcome resumed = run({"--run-dir", dir.string(), "--resume", "--quiet", "--iterations", "6"}, "L4");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  expect_same_run_files(a, dir);
}

TEST_F(CoordinatorProcessTest, CorruptCheckpointsAreRefusedNamingTheFile) {
  const fs::path a = reference_run();
  const fs::path checkpoint = a / "checkpoint.pb";
  const std::string good = read(checkpoint);
  ASSERT_GT(good.size(), 1000u);
  for (int k = 0; k < 12; ++k) {
    std::string bad = good;
    const size_t at = k < 4 ? static_cast<size_t>(8 + 4 * k) : good.size() * static_cast<size_t>(k) / 12;
    bad[at] = static_cast<char>(bad[at] ^ 0x20);
    std::ofstream(checkpoint, std::ios::binary | std::ios::trunc) << bad;
    const Outcome outcome = run({"--run-dir", a.string(), "--resume", "--quiet"}, "R" + std::to_string(k));
    EXPECT_EQ(outcome.code, 2) << "byte " << at << ": " << outcome.err;
    EXPECT_TRUE(contains(outcome.err, checkpoint.string() + ": ")) << outcome.err;
  }
  std::ofstream(checkpoint, std::ios::binary | std::ios::trunc) << good;
  const Outcome intact = run({"--run-dir", a.string(), "--resume", "--quiet"}, "R");
  EXPECT_EQ(intact.code, 0) << intact.err;
}

// A checkpoint whose mode and state disagree is refused before anything runs: the DIRECT_PATH run without its
// curriculum once crashed at the pair's first solve.
TEST_F(CoordinatorProcessTest, CheckpointsWhoseModeAndStateDisagreeAreRefused) {
  const fs::path dir = root_ / "M";
  const Outcome made = run({"--config", preset("direct_path.textproto"), "--run-dir", dir.string(), "--threads", "2",
                            "--quiet", "--iterations", "1"},
                           "M1");
  ASSERT_EQ(made.code, 0) << made.err;
  const fs::path file = dir / "checkpoint.pb";
  auto checkpoint = poet::read_checkpoint_file(file);
  ASSERT_TRUE(checkpoint) << checkpoint.error();
  ASSERT_GT(checkpoint->stages_size(), 0);
  checkpoint->clear_stages();
  std::ofstream(file, std::ios::binary | std::ios::trunc) << poet::encode_checkpoint_file(*checkpoint);
  const Outcome resumed = run({"--run-dir", dir.string(), "--resume", "--quiet", "--iterations", "5"}, "M2");
  EXPECT_EQ(resumed.code, 2) << resumed.err;
  EXPECT_TRUE(contains(resumed.err, file.string() + ": stages: none in mode DIRECT_PATH")) << resumed.err;
}

// σ decays to 1e-301 after the first step, so the second step's gradient (divided by σ) overflows Adam's second
// moment: the run stops there, and a resume stops at the same place with the same message.
TEST_F(CoordinatorProcessTest, ADivergingRunStopsAndSaysResumingWillRepeatIt) {
  const fs::path diverging = root_ / "diverging.textproto";
  std::ofstream(diverging) << "mode: POET\nseed: 7\niterations: 6\nes { perturbations: 4 sigma_decay: 1e-300 "
                              "sigma_floor: 0 }\nwalker { max_steps: 120 }\n";
  const fs::path dir = root_ / "V";
  const Outcome first = run({"--config", diverging.string(), "--run-dir", dir.string(), "--quiet"}, "V1");
  EXPECT_EQ(first.code, 1) << first.err;
  EXPECT_TRUE(contains(first.err, "the run diverged at iteration 1: pair 0")) << first.err;
  EXPECT_TRUE(contains(first.err, "Adam's second moment")) << first.err;
  EXPECT_TRUE(contains(first.err, "resuming from the last checkpoint will repeat this")) << first.err;
  EXPECT_FALSE(contains(first.err, "continue with --resume")) << first.err;
  EXPECT_EQ(checkpoint_iteration(dir), 1);
  const Outcome again = run({"--run-dir", dir.string(), "--resume", "--quiet"}, "V2");
  EXPECT_EQ(again.code, 1) << again.err;
  EXPECT_TRUE(contains(again.err, "the run diverged at iteration 1: pair 0")) << again.err;
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

TEST_F(CoordinatorProcessTest, HostileConfigsAreRefusedAtOnce) {
  const fs::path fifo = root_ / "fifo.textproto";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const Outcome from_fifo = run({"--config", fifo.string(), "--run-dir", (root_ / "F").string(), "--quiet"}, "F1");
  EXPECT_EQ(from_fifo.code, 2) << from_fifo.err;
  EXPECT_TRUE(contains(from_fifo.err, "not a regular file")) << from_fifo.err;

  const fs::path bad = root_ / "bad.textproto";
  const std::pair<const char*, const char*> cases[] = {
      {"", "mode:"},
      {"# only a comment\n", "mode:"},
      {"es { l2_coeff: 1e300 }\n", "es.l2_coeff"},
      {"es { init_lr: 1e300 }\n", "es.init_lr"},
      {"es { init_sigma: 1e308 }\n", "es.init_sigma"},
      {"poet { max_children: 2000000000 }\n", "poet.max_children"},
  };
  int k = 0;
  for (const auto& [text, field] : cases) {
    std::ofstream(bad, std::ios::trunc) << text;
    const std::string name = "F" + std::to_string(2 + k++);
    const Outcome outcome = run({"--config", bad.string(), "--run-dir", (root_ / name).string(), "--quiet"}, name);
    EXPECT_EQ(outcome.code, 2) << text << outcome.err;
    EXPECT_TRUE(contains(outcome.err, field)) << text << outcome.err;
    EXPECT_FALSE(fs::exists(root_ / name / "checkpoint.pb")) << text;
  }
}

// ZeroMQ would listen on port 99999 modulo 65536: a tcp:// port out of range is a bad command line, refused before
// anything is made or bound.
TEST_F(CoordinatorProcessTest, AListenPortOutOfRangeIsRefused) {
  for (const std::string port : {"99999", "0", "65536", "x"}) {
    const fs::path dir = root_ / ("L" + port);
    const Outcome outcome = run({"--config", config_.string(), "--run-dir", dir.string(), "--quiet", "--listen",
                                 "tcp://127.0.0.1:" + port, "--status-address", ""},
                                "L" + port);
    EXPECT_EQ(outcome.code, 2) << port << ": " << outcome.err;
    EXPECT_TRUE(contains(outcome.err, "1 to 65535")) << outcome.err;
    EXPECT_FALSE(fs::exists(dir)) << port;
  }
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

// Started again with its own config, a run directory's run is resumed (a restarted daemon runs the same command);
// with another config it is refused and left alone.
TEST_F(CoordinatorProcessTest, TheSameCommandResumesAnotherConfigIsRefused) {
  const fs::path a = reference_run();
  const std::string checkpoint = read(a / "checkpoint.pb");
  const Outcome same = run({"--config", config_.string(), "--run-dir", a.string(), "--quiet"}, "A2");
  EXPECT_EQ(same.code, 0) << same.err;
  EXPECT_TRUE(contains(same.err, "resumed")) << same.err;
  EXPECT_TRUE(read(a / "checkpoint.pb") == checkpoint);  // it was finished: nothing to add

  const fs::path other = root_ / "other.textproto";
  std::ofstream(other) << std::string(kTinyConfig) << "init_stddev: 0.2\n";
  const Outcome refused = run({"--config", other.string(), "--run-dir", a.string(), "--quiet"}, "A3");
  EXPECT_EQ(refused.code, 2);
  EXPECT_TRUE(contains(refused.err, "already holds a run of another config")) << refused.err;
  EXPECT_TRUE(read(a / "checkpoint.pb") == checkpoint);
}

// --start-from: the new run's first pair has the file's θ (here a walker from a random stream, written as the
// policies/ files are); a bad file is refused naming it, and the option is for new runs only.
TEST_F(CoordinatorProcessTest, StartFromGivesTheFirstPairThePolicysTheta) {
  poet::RandomStream stream(poet::stream_key(99, "start-from-test"));
  const std::vector<double> theta = poet::random_params(stream, 0.3);
  const fs::path policy = root_ / "walker.json";
  ASSERT_EQ(poet::save_policy(policy, theta, 250.0), std::nullopt);
  const fs::path dir = root_ / "S";
  const Outcome started = run({"--config", config_.string(), "--run-dir", dir.string(), "--quiet", "--iterations", "0",
                               "--start-from", policy.string()},
                              "S");
  ASSERT_EQ(started.code, 0) << started.err;
  EXPECT_TRUE(contains(started.err, "starts from")) << started.err;
  const poet::Expected<poet::PolicyFile> first = poet::load_policy(dir / "policies" / "pair-0.json");
  ASSERT_TRUE(first) << first.error();
  EXPECT_EQ(first->params, theta);
  // the run goes on from there like any other
  const Outcome resumed = run({"--run-dir", dir.string(), "--resume", "--quiet", "--iterations", "1"}, "S2");
  EXPECT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(poet::load_policy(dir / "policies" / "pair-0.json")->params, theta);

  std::ofstream(root_ / "bad.json") << "[[1, 2, 3], 5]";
  const Outcome bad = run({"--config", config_.string(), "--run-dir", (root_ / "B").string(), "--quiet", "--start-from",
                           (root_ / "bad.json").string()},
                          "B");
  EXPECT_EQ(bad.code, 2);
  EXPECT_TRUE(contains(bad.err, "bad.json")) << bad.err;
  EXPECT_FALSE(fs::exists(root_ / "B" / "checkpoint.pb"));
  const Outcome with_resume = run({"--run-dir", dir.string(), "--resume", "--start-from", policy.string()}, "R");
  EXPECT_EQ(with_resume.code, 2) << with_resume.err;
}

}  // namespace

// The README's main job, cut short: the quick preset admits children (iteration 6) and accepts a transfer
// (iteration 8) within its first nine iterations.
// The README's main job: from the shipped walker, children with obstacles are admitted and solved (walkers on
// courses harder than flat) and transfers accepted within its first reproductions.
TEST_F(CoordinatorProcessTest, QuickPresetFromTheWalkerSolvesChildrenAndAcceptsTransfers) {
  const fs::path dir = root_ / "quick";
  const Outcome outcome = run({"--config", preset("quick.textproto"), "--run-dir", dir.string(), "--start-from",
                               std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json", "--threads", "2",
                               "--quiet", "--iterations", "9"},
                              "quick");
  ASSERT_EQ(outcome.code, 0) << outcome.err;
  const std::string events = read(dir / "events.jsonl");
  EXPECT_TRUE(contains(events, R"("event":"pair_created")")) << events;
  EXPECT_TRUE(contains(events, R"("event":"transfer")")) << events;
  EXPECT_TRUE(contains(events, R"("event":"solved","pair":1)")) << events;
  EXPECT_TRUE(fs::exists(dir / "envs" / "pair-1.env.json"));
  EXPECT_TRUE(fs::exists(dir / "policies" / "pair-1.best.json"));
}

// Each control preset runs end to end as a mode of the same command.
TEST_F(CoordinatorProcessTest, ControlPresetsRun) {
  for (const std::string name : {"es_alone", "direct_path", "no_transfer"}) {
    const fs::path dir = root_ / name;
    const Outcome outcome = run({"--config", preset(name + ".textproto"), "--run-dir", dir.string(), "--threads", "2",
                                 "--quiet", "--iterations", "2"},
                                name);
    EXPECT_EQ(outcome.code, 0) << name << ": " << outcome.err;
    EXPECT_TRUE(contains(read(dir / "pair_stats.csv"), "\n1,0,")) << name;  // iteration 1 of pair 0 logged
  }
}
