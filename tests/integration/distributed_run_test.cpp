// The coordinator with ZeroMQ workers, as real processes on loopback: runs with 1, 2 or 3 local workers end in
// the files of a run on threads, byte for byte; a worker killed with SIGKILL mid-run changes nothing; a run
// started with no worker waits and completes once one connects, and one whose every worker leaves waits for the
// next; a worker that heartbeats but never answers only delays the run (its job is taken back after a lease); a
// coordinator killed with SIGKILL and started again finds its workers back and ends in the same files; a job that
// kills every worker stops the run naming the task; the status socket answers during a run. A CPPN run on workers,
// killed and resumed, ends as on threads. A worker given --coordinator-file follows the coordinator of a run that
// moved, and waits, saying why, while the file is missing or broken.

#include <gtest/gtest.h>
#include <httplib.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "coordinator_run_fixture.h"
#include "rogue_peer.h"

namespace {

using namespace poet::testing;
namespace fs = std::filesystem;
using namespace std::chrono_literals;
class DistributedRunTest : public CoordinatorRunTest {
 protected:
  // Runs config_ on two workers over --listen, kills the coordinator with SIGKILL past its first checkpoint,
  // starts it again, and expects the workers found again and the files of the run on threads.
  void kill_and_resume_on_workers() {
    const fs::path reference = threads_run();
    const int port = free_port();
    ASSERT_GT(port, 0);
    const std::string endpoint = "tcp://127.0.0.1:" + std::to_string(port);
    const pid_t before = coordinator(root_ / "R", {"--listen", endpoint}, "before");
    await_log("before", "workers connect to (tcp://)");
    std::vector<pid_t> workers;
    for (const char* name : {"a", "b"})
      workers.push_back(spawn(POET_WORKER_BIN, {"--connect", endpoint, "--threads", "1"}, name));
    await_log("before", "(iteration [2-9]):");  // past the first checkpoint (checkpoint_interval 1)
    ASSERT_EQ(::kill(before, SIGKILL), 0);
    EXPECT_EQ(wait(before), 128 + SIGKILL);
    EXPECT_NE(read(root_ / "R" / "events.jsonl"), read(reference / "events.jsonl")) << "the run ended before the kill";

    const pid_t after = coordinator(root_ / "R", {"--listen", endpoint}, "after");
    EXPECT_EQ(wait(after), 0) << read(root_ / "after.err");
    const std::string log = read(root_ / "after.err");
    EXPECT_TRUE(contains(log, "resum")) << log;
    EXPECT_TRUE(contains(log, "joined")) << log;
    expect_same_run(reference, root_ / "R");
    for (pid_t worker : workers)
      EXPECT_EQ(wait(worker), 0) << "the workers stay until the restarted run shuts them down";
    const std::string worker_log = read(root_ / "a.err") + read(root_ / "b.err");
    EXPECT_TRUE(contains(worker_log, "Hello again") || contains(worker_log, "connecting again")) << worker_log;
  }
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

// Far more workers than tasks in a batch (the tiny config's batches are of 8 to 60 tasks): most hold nothing most
// of the time, and the run is still the threads' one.
TEST_F(DistributedRunTest, TwoHundredFiftySixWorkersGiveTheRunOfThreads) {
  const fs::path reference = threads_run();
  const auto started = std::chrono::steady_clock::now();
  const pid_t pid = coordinator(root_ / "w256", {"--local-workers", "256"}, "w256");
  ASSERT_EQ(wait(pid), 0) << read(root_ / "w256.err");
  EXPECT_TRUE(contains(read(root_ / "w256.err"), "started 256 local workers"));
  expect_same_run(reference, root_ / "w256");
  std::printf("256 local workers: the run took %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
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
  ASSERT_EQ(children_.ended(pid), std::nullopt) << "the run ended before the kill";
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
  EXPECT_EQ(wait(worker), 0) << "the worker leaves when the run is finished\n" << read(root_ / "worker.err");
}

// A worker given --coordinator-file follows the run's coordinator.endpoint: to the first coordinator, and, once that
// one stopped at a boundary (SIGUSR1, as before a SLURM time limit) and a second resumed the run on another port,
// to the second, which finishes the run as on threads. The file is there while a coordinator runs, and only then.
TEST_F(DistributedRunTest, AWorkerFollowsTheEndpointFileToACoordinatorThatMoved) {
  std::ofstream(config_, std::ios::trunc) << config_with("perturbations: 4", "perturbations: 24");
  const fs::path reference = threads_run();
  const fs::path run_dir = root_ / "M";
  const fs::path file = run_dir / "coordinator.endpoint";
  const pid_t first = coordinator(run_dir, {"--listen", "tcp://127.0.0.1:*"}, "first");
  const std::string first_endpoint = await_log("first", "workers reach this coordinator at (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(first_endpoint.empty());
  EXPECT_TRUE(contains(read(file), "endpoint=" + first_endpoint + "\n")) << read(file);
  const pid_t worker = spawn(POET_WORKER_BIN, {"--coordinator-file", file.string(), "--threads", "2"}, "worker");
  await_log("first", "(iteration [1-9]):");
  ASSERT_EQ(::kill(first, SIGUSR1), 0);
  ASSERT_EQ(wait(first), 3) << read(root_ / "first.err");
  EXPECT_FALSE(fs::exists(file)) << "a coordinator that stopped leaves its endpoint behind";
  ASSERT_NE(read(run_dir / "events.jsonl"), read(reference / "events.jsonl")) << "the run ended before the stop";

  const pid_t second = coordinator(run_dir, {"--listen", "tcp://127.0.0.1:*"}, "second");
  const std::string second_endpoint = await_log("second", "workers reach this coordinator at (tcp://[0-9.]+:[0-9]+)");
  EXPECT_NE(second_endpoint, first_endpoint);
  EXPECT_EQ(wait(second), 0) << read(root_ / "second.err");
  expect_same_run(reference, run_dir);
  EXPECT_EQ(wait(worker), 0) << "the worker leaves when the run is finished\n" << read(root_ / "worker.err");
  const std::string worker_log = read(root_ / "worker.err");
  EXPECT_TRUE(contains(worker_log, "gives the coordinator at " + first_endpoint)) << worker_log;
  EXPECT_TRUE(contains(worker_log, "gives the coordinator at " + second_endpoint)) << worker_log;
  EXPECT_FALSE(fs::exists(file));
}

// A worker whose --coordinator-file is missing, broken or names a coordinator key other than the one it was given
// waits and says why; SIGUSR1 (a scheduler's warning, meant for the coordinator) does not end it.
TEST_F(DistributedRunTest, AWorkerWaitsForAnEndpointFileThatIsMissingOrBroken) {
  const fs::path file = root_ / "coordinator.endpoint";
  const pid_t worker = spawn(POET_WORKER_BIN, {"--coordinator-file", file.string(), "--threads", "1"}, "worker");
  await_log("worker", "(does not exist); trying again");
  std::ofstream(file) << "endpoint=tcp://127.0.0.1:99999\n";
  await_log("worker", "line 1: (.*); trying again");
  ASSERT_EQ(children_.ended(worker), std::nullopt);
  ASSERT_EQ(::kill(worker, SIGUSR1), 0);  // what a scheduler may send every process of a job: ignored
  ASSERT_EQ(::kill(worker, SIGTERM), 0);
  EXPECT_EQ(wait(worker), 0);

  // the coordinator key given in --curve-keys is the one trusted: a file naming another is refused
  const fs::path keys = root_ / "keys";
  for (const std::string who : {"coordinator", "worker"})
    ASSERT_EQ(wait(spawn(POETCTL_BIN, {"keygen", keys.string(), who}, "keygen-" + who)), 0);
  std::ofstream(file, std::ios::trunc) << "endpoint=tcp://127.0.0.1:5\n"
                                       << "curve_public_key=rq:rM>}U?@Lns47E1%kR.o@n%FcmmsL/@{H8]yf7\n";
  const pid_t keyed = spawn(
      POET_WORKER_BIN, {"--coordinator-file", file.string(), "--curve-keys", keys.string(), "--threads", "1"}, "keyed");
  await_log("keyed", "(its curve_public_key is not the coordinator.key of --curve-keys)");
  ASSERT_EQ(::kill(keyed, SIGTERM), 0);
  EXPECT_EQ(wait(keyed), 0);
}

TEST_F(DistributedRunTest, ARunWhoseWorkersAllLeaveWaitsForTheNext) {
  std::ofstream(config_, std::ios::trunc) << config_with("perturbations: 4", "perturbations: 24");
  const fs::path reference = threads_run();
  const pid_t pid = coordinator(root_ / "L", {"--listen", "tcp://127.0.0.1:*"}, "L");
  const std::string endpoint = await_log("L", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(endpoint.empty());
  const pid_t first = spawn(POET_WORKER_BIN, {"--connect", endpoint, "--threads", "1"}, "first");
  await_log("L", "(iteration [0-9]+):");
  ASSERT_EQ(children_.ended(pid), std::nullopt) << "the run ended before the worker left";
  ASSERT_EQ(::kill(first, SIGTERM), 0);
  EXPECT_EQ(wait(first), 0);
  await_log("L", "worker 0x[0-9a-f]+ (left): 0 connected");
  await_log("L", "(waiting for workers)");
  const pid_t second = spawn(POET_WORKER_BIN, {"--connect", endpoint, "--threads", "2"}, "second");
  EXPECT_EQ(wait(pid), 0) << read(root_ / "L.err");
  expect_same_run(reference, root_ / "L");
  EXPECT_EQ(wait(second), 0);
}

TEST_F(DistributedRunTest, AWorkerThatNeverAnswersOnlyDelaysTheRun) {
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 4");  // each batch waits
  const fs::path reference = threads_run();
  const pid_t pid = coordinator(root_ / "S", {"--listen", "tcp://127.0.0.1:*"}, "S");
  const std::string endpoint = await_log("S", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(endpoint.empty());
  // it joins first, so the first jobs of the run are its
  const pid_t silent =
      spawn(POET_TEST_WORKER_BIN,
            {"--connect", endpoint, "--threads", "1", "--fault", "ignore-jobs", "--log-level", "debug"}, "silent");
  await_log("silent", "(welcomed) by the coordinator");
  const pid_t healthy = spawn(POET_WORKER_BIN, {"--connect", endpoint, "--threads", "2"}, "healthy");
  EXPECT_EQ(wait(pid), 0) << read(root_ / "S.err");
  expect_same_run(reference, root_ / "S");
  EXPECT_TRUE(contains(read(root_ / "silent.err"), "ignored (--fault ignore-jobs)")) << "it held jobs and kept them";
  EXPECT_TRUE(contains(read(root_ / "S.err"), "given no more jobs")) << read(root_ / "S.err");
  EXPECT_EQ(wait(silent), 0);
  EXPECT_EQ(wait(healthy), 0);
}

TEST_F(DistributedRunTest, ACoordinatorKilledMidRunFindsItsWorkersAgainAndEndsTheSame) {
  std::ofstream(config_, std::ios::trunc) << config_with("perturbations: 4", "perturbations: 24");
  kill_and_resume_on_workers();
}

// Enhanced POET's CPPN terrain travels to workers and resumes like any course.
TEST_F(DistributedRunTest, ACppnRunOnWorkersKilledAndResumedEndsAsOnThreads) {
  std::string config = config_with("perturbations: 4", "perturbations: 24");
  config.replace(config.find("active_cap: 3"), 13, "active_cap: 3 environments: CPPN_TERRAIN novelty: PATA_EC");
  std::ofstream(config_, std::ios::trunc) << config;
  kill_and_resume_on_workers();
  EXPECT_TRUE(contains(read(root_ / "R" / "events.jsonl"), "cppn-"));
}

TEST_F(DistributedRunTest, AJobThatKillsEveryWorkerStopsTheRunNamingTheTask) {
  // the local workers, poet-test-worker, inherit the coordinator's environment and crash on their first job
  ChildOptions crashing;
  crashing.environment = std::vector<std::string>{"POET_TEST_WORKER_FAULT=crash-on-job"};
  for (char** variable = environ; *variable != nullptr; ++variable) crashing.environment->push_back(*variable);
  const pid_t pid = coordinator(root_ / "P", {"--local-workers", "2", "--worker-binary", POET_TEST_WORKER_BIN}, "P",
                                crashing);
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
    if (std::string_view(path) != "/metrics") {  // Prometheus text; every other endpoint answers JSON
      EXPECT_TRUE(nlohmann::json::accept(response->body)) << path << ": " << response->body;
    }
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
  EXPECT_EQ(wait(pid), 143);
}

}  // namespace
