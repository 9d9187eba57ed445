// The coordinator with ZeroMQ workers, as real processes on loopback: runs with 1, 2 or 3 local workers end in
// the files of a run on threads, byte for byte; a worker killed with SIGKILL mid-run changes nothing; a run
// started with no worker waits and completes once one connects; a job that kills every worker stops the run
// naming the task; the status socket answers during a run.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"

namespace {

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

const char* const kRunFiles[] = {"checkpoint.pb", "events.jsonl", "pair_stats.csv"};

using poet::testing::exit_code;
using poet::testing::spawn_child;
std::string read(const fs::path& path) { return poet::testing::read_file(path); }

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

// The children of a process (its local workers), from /proc.
std::vector<pid_t> children_of(pid_t pid) {
  std::vector<pid_t> out;
  std::error_code ec;
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
    std::ifstream in(task.path() / "children");
    for (pid_t child; in >> child;) out.push_back(child);
  }
  return out;
}

class DistributedRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() / ("poet_distributed_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
    config_ = root_ / "tiny.textproto";
    std::ofstream(config_) << kConfig;
  }
  void TearDown() override {
    for (pid_t pid : children_) {
      for (pid_t worker : children_of(pid)) ::kill(worker, SIGKILL);
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
    fs::remove_all(root_);
  }

  pid_t spawn(const char* binary, std::vector<std::string> args, const std::string& name) {
    args.insert(args.begin(), binary);
    const pid_t pid = spawn_child(args, root_ / (name + ".out"), root_ / (name + ".err"));
    EXPECT_GT(pid, 0) << "posix_spawn " << binary;
    if (pid > 0) children_.push_back(pid);
    return pid;
  }

  pid_t coordinator(const fs::path& dir, std::vector<std::string> extra, const std::string& name) {
    std::vector<std::string> args = {"--config",         config_.string(), "--run-dir",     dir.string(), "--quiet",
                                     "--status-address", "127.0.0.1:0",    "--liveness-ms", "1000"};
    args.insert(args.end(), extra.begin(), extra.end());
    return spawn(POET_COORDINATOR_BIN, args, name);
  }

  // Waits (at most two minutes) for the process to end; its exit code, or -1 when it did not.
  int wait(pid_t pid) {
    const auto deadline = std::chrono::steady_clock::now() + 120s;
    int status = 0;
    while (std::chrono::steady_clock::now() < deadline) {
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        std::erase(children_, pid);
        return exit_code(status);
      }
      std::this_thread::sleep_for(10ms);
    }
    ADD_FAILURE() << "process " << pid << " did not end";
    return -1;
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

  fs::path root_;
  fs::path config_;
  std::vector<pid_t> children_;
};

TEST_F(DistributedRunTest, AnyNumberOfWorkersGivesTheRunOfThreads) {
  const fs::path reference = threads_run();
  for (int workers : {1, 2, 3}) {
    const std::string name = "w" + std::to_string(workers);
    const pid_t pid = coordinator(root_ / name, {"--local-workers", std::to_string(workers)}, name);
    ASSERT_EQ(wait(pid), 0) << read(root_ / (name + ".err"));
    EXPECT_TRUE(contains(read(root_ / (name + ".err")), "started " + std::to_string(workers) + " local workers"));
    expect_same_run(reference, root_ / name);
  }
}

// The config with one line replaced.
std::string config_with(const std::string& from, const std::string& to) {
  std::string text = kConfig;
  return text.replace(text.find(from), from.size(), to);
}

TEST_F(DistributedRunTest, AWorkerKilledMidRunChangesNothing) {
  std::ofstream(config_, std::ios::trunc) << config_with("perturbations: 4", "perturbations: 24");  // a longer run
  const fs::path reference = threads_run();
  const pid_t pid = coordinator(root_ / "K", {"--local-workers", "2"}, "K");
  await_log("K", "(started) 2 local workers");
  std::vector<pid_t> workers;
  for (int i = 0; i < 500 && workers.size() < 2; ++i) {
    workers = children_of(pid);
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_EQ(workers.size(), 2u);
  await_log("K", "(iteration [0-9]+):");  // the run is under way: its first event
  ASSERT_EQ(::waitpid(pid, nullptr, WNOHANG), 0) << "the run ended before the kill";
  ASSERT_EQ(::kill(workers[0], SIGKILL), 0);
  EXPECT_EQ(wait(pid), 0) << read(root_ / "K.err");
  expect_same_run(reference, root_ / "K");
}

TEST_F(DistributedRunTest, ARunWithoutWorkersWaitsForOne) {
  const fs::path reference = threads_run();
  const pid_t pid = coordinator(root_ / "N", {"--listen", "tcp://127.0.0.1:*"}, "N");
  const std::string endpoint = await_log("N", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(endpoint.empty());
  await_log("N", "(waiting for workers)");
  const pid_t worker = spawn(POET_WORKER_BIN, {"--connect", endpoint, "--threads", "2"}, "worker");
  EXPECT_EQ(wait(pid), 0) << read(root_ / "N.err");
  expect_same_run(reference, root_ / "N");
  EXPECT_EQ(wait(worker), 0) << "the worker leaves when the run is finished";
}

TEST_F(DistributedRunTest, AJobThatKillsEveryWorkerStopsTheRunNamingTheTask) {
  const pid_t pid =
      coordinator(root_ / "P", {"--local-workers", "2", "--worker-arg=--fault", "--worker-arg=crash-on-job"}, "P");
  EXPECT_EQ(wait(pid), 1);
  const std::string err = read(root_ / "P.err");
  EXPECT_TRUE(contains(err, "of the batch (course")) << err;
  EXPECT_TRUE(contains(err, "workers when they died")) << err;
}

TEST_F(DistributedRunTest, TheStatusSocketAnswersDuringARun) {
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 99");
  const pid_t pid = coordinator(root_ / "S", {"--local-workers", "1"}, "S");
  const std::string port = await_log("S", "status: http://127.0.0.1:([0-9]+)/status");
  ASSERT_FALSE(port.empty());
  await_log("S", "(iteration [0-9]+):");
  httplib::Client client("127.0.0.1", std::stoi(port));
  client.set_connection_timeout(5);
  client.set_read_timeout(5);
  for (const char* path : {"/status", "/pairs", "/archive", "/workers", "/events?since=0", "/healthz", "/metrics"}) {
    const auto response = client.Get(path);
    ASSERT_TRUE(response) << path;
    EXPECT_EQ(response->status, 200) << path << ": " << response->body;
  }
  std::string body;
  for (int i = 0; i < 50 && !contains(body, R"("workers":1)"); ++i) {  // the dispatcher publishes twice a second
    const auto status = client.Get("/status");
    ASSERT_TRUE(status);
    body = status->body;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_TRUE(contains(body, R"("workers":1)")) << body;
  EXPECT_EQ(client.Get("/nowhere")->status, 404);
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  EXPECT_EQ(wait(pid), 130);
}

}  // namespace
