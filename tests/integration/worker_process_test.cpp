// Tests the poet-worker process end to end. The test plays the coordinator with a real ROUTER socket on an
// ephemeral loopback port and starts real worker processes: Hello carries this build's fingerprint and repeats
// until Welcome; jobs come back bit for bit equal to run_task in this process; θ travels once per batch;
// heartbeats flow while idle and while a job runs; hostile frames are survived; Refused exits 2 and Shutdown 0;
// a restarted coordinator is found again; SIGTERM abandons a long job with a Goodbye; poet-test-worker's faults
// do what the coordinator's tests need, and poet-worker has none of them; an unreachable coordinator and a peer
// that speaks another protocol are reported for what they are. The fixture kills its children and removes its
// files even on failure.

#include <gtest/gtest.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <bit>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>

#include "child_process.h"
#include "common/formats/rollout_task_proto.h"
#include "common/program/build_fingerprint.h"
#include "loopback_port.h"
#include "scratch_dir.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"
#include "wire.pb.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using poet::testing::contains;
using poet::testing::read_file;
using Clock = std::chrono::steady_clock;
using Millis = std::chrono::milliseconds;

// The Welcome the fake coordinator gives: short, so liveness tests take a second, not minutes.
constexpr uint32_t kHeartbeatMs = 100;
constexpr uint32_t kLivenessMs = 600;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Resident memory of a process in kB (VmRSS), or -1.
long rss_kb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.starts_with("VmRSS:")) return std::stol(line.substr(6));
  }
  return -1;
}

std::vector<double> test_theta(uint64_t seed) {
  RandomStream rng(stream_key(seed, "init"));
  return random_params(rng);
}

RolloutTask make_task(const std::shared_ptr<const std::vector<double>>& theta, const std::string& course, uint32_t seed,
                      int max_steps, std::optional<Perturbation> perturbation = std::nullopt) {
  RolloutTask task;
  task.theta = theta;
  task.env = EnvDef{*named_course(course), seed};
  task.perturbation = perturbation;
  task.max_steps = max_steps;
  return task;
}

// The tasks of the bit-for-bit test: named courses, with and without perturbations, both lidar rules, short.
std::vector<RolloutTask> mixed_tasks(const std::shared_ptr<const std::vector<double>>& theta) {
  std::vector<RolloutTask> tasks = {
      make_task(theta, "flat", 1, 200),
      make_task(theta, "r1", 2, 150, Perturbation{.key = 11, .sign = 1, .sigma = 0.05}),
      make_task(theta, "r1", 2, 150, Perturbation{.key = 11, .sign = -1, .sigma = 0.05}),
      make_task(theta, "hard", 3, 250, Perturbation{.key = 12, .sign = 1, .sigma = 0.1}),
      make_task(theta, "hardcore-like", 4, 120),
      make_task(theta, "r3", 5, 180, Perturbation{.key = 13, .sign = -1, .sigma = 0.02}),
  };
  tasks[4].walker.lidar = LidarRule::kFirst;
  tasks[4].walker.push_scale = 0;
  return tasks;
}

wire::CoordinatorMessage job_message(uint64_t job_id, uint64_t batch_id, const std::vector<double>* theta,
                                     const std::vector<RolloutTask>& tasks) {
  wire::CoordinatorMessage message;
  wire::Job& job = *message.mutable_job();
  job.set_job_id(job_id);
  job.set_batch_id(batch_id);
  if (theta != nullptr) {
    wire::Theta& t = *job.add_thetas();
    t.set_hash(theta_hash(*theta));
    for (double v : *theta) t.add_values(v);
  }
  for (const RolloutTask& task : tasks) *job.add_tasks() = to_wire(task, theta_hash(*task.theta));
  return message;
}

// Every result equal to run_task's in this process, to the bit.
void expect_results_equal_run_task(const wire::Result& result, const std::vector<RolloutTask>& tasks) {
  EXPECT_FALSE(result.has_error()) << result.error();
  ASSERT_EQ(result.results_size(), static_cast<int>(tasks.size()));
  for (size_t i = 0; i < tasks.size(); ++i) {
    const RolloutResult expected = run_task(tasks[i]);
    const wire::TaskResult& got = result.results(static_cast<int>(i));
    EXPECT_EQ(std::bit_cast<uint64_t>(got.total_reward()), std::bit_cast<uint64_t>(expected.total_reward))
        << "task " << i << ": " << got.total_reward() << " vs " << expected.total_reward;
    EXPECT_EQ(got.steps(), expected.steps) << "task " << i;
    EXPECT_EQ(got.finished(), expected.finished) << "task " << i;
    EXPECT_EQ(got.fell(), expected.fell) << "task " << i;
  }
}

struct Received {
  std::string peer;  // the ROUTER's routing id of the sender
  wire::WorkerMessage message;
};

// A fresh directory and a ROUTER per test; every worker still running is killed and the directory removed, even
// on failure.
class WorkerProcessTest : public ::testing::Test {
 protected:
  void SetUp() override { bind("tcp://127.0.0.1:*"); }

  void TearDown() override {
    children_.kill_all();
    router_.reset();
  }

  // (Re)binds the ROUTER; a port just released may take a moment to be free again.
  void bind(const std::string& endpoint) {
    router_.reset();
    welcomed_.clear();
    const auto deadline = Clock::now() + 5s;
    for (;;) {
      router_.emplace(context_, zmq::socket_type::router);
      router_->set(zmq::sockopt::linger, 0);
      router_->set(zmq::sockopt::router_mandatory, 1);
      try {
        router_->bind(endpoint);
        break;
      } catch (const zmq::error_t& e) {
        router_.reset();
        if (e.num() != EADDRINUSE || Clock::now() > deadline) {
          ADD_FAILURE() << "bind " << endpoint << ": " << e.what();
          return;
        }
        std::this_thread::sleep_for(20ms);
      }
    }
    endpoint_ = router_->get(zmq::sockopt::last_endpoint);
  }

  // Starts poet-worker (2 threads, named "test-worker", connected to the ROUTER) with extra args; its output
  // goes to files named after `name`. A test of a fault starts poet-test-worker (`binary`) the same way.
  pid_t spawn(const std::vector<std::string>& extra = {}, const std::string& name = "worker",
              std::optional<std::string> endpoint = std::nullopt, const char* binary = POET_WORKER_BIN) {
    std::vector<std::string> all = {binary,   "--connect",  endpoint.value_or(endpoint_), "--threads", "2",
                                    "--name", "test-worker"};
    all.insert(all.end(), extra.begin(), extra.end());
    return spawn_raw(all, name);
  }

  pid_t spawn_raw(std::vector<std::string> all, const std::string& name) {
    return children_.start(std::move(all), root_ / name);
  }

  std::string err(const std::string& name = "worker") { return read_file(root_ / (name + ".err")); }

  // Sends one frame to a worker; false when it is gone.
  bool send_raw(const std::string& peer, const std::string& bytes) {
    try {
      if (!router_->send(zmq::buffer(peer), zmq::send_flags::sndmore | zmq::send_flags::dontwait)) return false;
      return router_->send(zmq::buffer(bytes), zmq::send_flags::dontwait).has_value();
    } catch (const zmq::error_t& e) {
      if (e.num() == EHOSTUNREACH) return false;
      throw;
    }
  }
  bool send(const std::string& peer, const wire::CoordinatorMessage& message) {
    return send_raw(peer, message.SerializeAsString());
  }

  // The next message from any worker within `timeout`, or nothing. Meanwhile, like a coordinator, it sends a
  // Heartbeat to every welcomed worker every heartbeat interval.
  std::optional<Received> receive(Millis timeout) {
    const auto deadline = Clock::now() + timeout;
    for (;;) {
      heartbeat_welcomed();
      const auto left = std::chrono::ceil<Millis>(deadline - Clock::now());
      if (left <= 0ms) return std::nullopt;
      zmq_pollitem_t item{router_->handle(), 0, ZMQ_POLLIN, 0};
      zmq::poll(&item, 1, std::min(left, Millis(10)));
      if ((item.revents & ZMQ_POLLIN) == 0) continue;
      zmq::message_t peer;
      zmq::message_t body;
      EXPECT_TRUE(router_->recv(peer));
      EXPECT_TRUE(peer.more());
      EXPECT_TRUE(router_->recv(body));
      EXPECT_FALSE(body.more()) << "a worker sent a message of several frames";
      Received r{peer.to_string(), {}};
      EXPECT_TRUE(r.message.ParseFromArray(body.data(), static_cast<int>(body.size())))
          << "a frame that does not parse";
      if (r.message.has_heartbeat()) ++heartbeats_[r.peer];
      return r;
    }
  }

  // The next message of `kind`, skipping others (heartbeats are counted), within `timeout`.
  std::optional<Received> receive(wire::WorkerMessage::KindCase kind, Millis timeout) {
    const auto deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      auto r = receive(std::chrono::ceil<Millis>(deadline - Clock::now()));
      if (r && r->message.kind_case() == kind) return r;
    }
    return std::nullopt;
  }

  void heartbeat_welcomed() {
    if (Clock::now() - last_heartbeat_ < Millis(kHeartbeatMs)) return;
    last_heartbeat_ = Clock::now();
    wire::CoordinatorMessage heartbeat;
    heartbeat.mutable_heartbeat();
    for (auto it = welcomed_.begin(); it != welcomed_.end();) {
      it = send(*it, heartbeat) ? std::next(it) : welcomed_.erase(it);
    }
  }

  // Waits for a Hello and welcomes its sender; returns the sender's routing id.
  std::string welcome_worker(Millis timeout = 10s) {
    const auto hello = receive(wire::WorkerMessage::kHello, timeout);
    if (!hello) {
      ADD_FAILURE() << "no Hello; worker log:\n" << err();
      return {};
    }
    wire::CoordinatorMessage welcome;
    welcome.mutable_welcome()->set_heartbeat_ms(kHeartbeatMs);
    welcome.mutable_welcome()->set_liveness_ms(kLivenessMs);
    EXPECT_TRUE(send(hello->peer, welcome));
    welcomed_.insert(hello->peer);
    return hello->peer;
  }

  // The Result of job_id (other messages skipped), within `timeout`.
  std::optional<wire::Result> result_of(uint64_t job_id, Millis timeout = 60s) {
    const auto deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      auto r = receive(wire::WorkerMessage::kResult, std::chrono::ceil<Millis>(deadline - Clock::now()));
      if (r && r->message.result().job_id() == job_id) return r->message.result();
    }
    ADD_FAILURE() << "no Result for job " << job_id << "; worker log:\n" << err();
    return std::nullopt;
  }

  // Waits for a worker to end (bounded), answering heartbeats meanwhile; its exit code (128 + signal), or -1.
  int wait_exit(pid_t pid, Millis timeout) {
    return children_.wait(pid, timeout, [&] { receive(5ms); }).value_or(-1);
  }

  // the children go first, the directory after them
  poet::testing::ScratchDir scratch_{"poet_worker_process_test"};
  fs::path root_ = scratch_.path();
  poet::testing::Children children_;
  zmq::context_t context_{1};
  std::optional<zmq::socket_t> router_;
  std::string endpoint_;
  std::set<std::string> welcomed_;
  std::map<std::string, int> heartbeats_;
  Clock::time_point last_heartbeat_{};
};

TEST_F(WorkerProcessTest, HelloCarriesThisBuildsFingerprintAndRepeatsUntilWelcome) {
  spawn();
  const auto first = receive(wire::WorkerMessage::kHello, 10s);
  ASSERT_TRUE(first) << err();
  const auto first_at = Clock::now();
  const wire::Hello& hello = first->message.hello();
  EXPECT_EQ(hello.protocol_version(), static_cast<uint32_t>(wire::PROTOCOL_VERSION));
  EXPECT_EQ(hello.fingerprint_digest(), build_fingerprint_digest());
  EXPECT_EQ(hello.fingerprint(), build_fingerprint());
  EXPECT_EQ(hello.threads(), 2u);
  EXPECT_EQ(hello.name(), "test-worker");
  // no Welcome: the Hello comes again a second later
  const auto second = receive(wire::WorkerMessage::kHello, 3s);
  ASSERT_TRUE(second);
  EXPECT_NEAR(seconds_since(first_at), 1.0, 0.3);
  EXPECT_EQ(second->peer, first->peer);
}

TEST_F(WorkerProcessTest, DefaultNameIsHostAndPid) {
  const pid_t pid = spawn_raw({POET_WORKER_BIN, "--connect", endpoint_, "--threads", "1"}, "worker");
  const auto hello = receive(wire::WorkerMessage::kHello, 10s);
  ASSERT_TRUE(hello) << err();
  EXPECT_TRUE(hello->message.hello().name().ends_with(":" + std::to_string(pid))) << hello->message.hello().name();
  EXPECT_EQ(hello->message.hello().threads(), 1u);
}

TEST_F(WorkerProcessTest, WorkerStartedBeforeTheCoordinatorFindsItWhenItComesUp) {
  const std::string endpoint = endpoint_;
  router_.reset();  // nobody listens yet
  const pid_t pid = spawn({}, "worker", endpoint);
  std::this_thread::sleep_for(1500ms);
  bind(endpoint);
  ASSERT_FALSE(welcome_worker().empty());
  // exactly one Hello per second at most: no burst of queued Hellos from the time nobody listened
  int hellos = 0;
  const auto until = Clock::now() + 500ms;
  while (Clock::now() < until) {
    const auto r = receive(100ms);
    if (r && r->message.has_hello()) ++hellos;
  }
  EXPECT_LE(hellos, 1);
  EXPECT_GT(rss_kb(pid), 0);
}

TEST_F(WorkerProcessTest, HeartbeatsArriveWhileIdle) {
  const pid_t pid = spawn();
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  heartbeats_.clear();
  const auto until = Clock::now() + 1s;
  while (Clock::now() < until) {
    const auto r = receive(50ms);
    if (r) {
      EXPECT_TRUE(r->message.has_heartbeat()) << r->message.ShortDebugString();
    }
  }
  EXPECT_GE(heartbeats_[peer], 7);
  EXPECT_LE(heartbeats_[peer], 13);
  std::printf("idle worker RSS: %ld kB\n", rss_kb(pid));
}

TEST_F(WorkerProcessTest, JobResultsEqualRunTaskBitForBit) {
  const pid_t pid = spawn();
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  const std::vector<double> theta = test_theta(7);
  const auto shared = std::make_shared<const std::vector<double>>(theta);
  const std::vector<RolloutTask> tasks = mixed_tasks(shared);
  ASSERT_TRUE(send(peer, job_message(101, 1, &theta, tasks)));
  const auto result = result_of(101);
  ASSERT_TRUE(result);
  expect_results_equal_run_task(*result, tasks);
  const long rss = rss_kb(pid);
  std::printf("worker RSS after a job: %ld kB\n", rss);
  EXPECT_LE(rss, 50 * 1024);
}

TEST_F(WorkerProcessTest, JobsOfABatchNameThetaByHashOnceSent) {
  spawn();
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  const std::vector<double> theta = test_theta(8);
  const auto shared = std::make_shared<const std::vector<double>>(theta);
  const std::vector<RolloutTask> first = {make_task(shared, "flat", 1, 60)};
  const std::vector<RolloutTask> second = {
      make_task(shared, "r1", 9, 80, Perturbation{.key = 5, .sign = -1, .sigma = 0.1}),
      make_task(shared, "hard", 10, 80)};
  // sent several ahead: queued, run in order
  ASSERT_TRUE(send(peer, job_message(1, 40, &theta, first)));
  ASSERT_TRUE(send(peer, job_message(2, 40, nullptr, second)));
  const auto r1 = result_of(1);
  const auto r2 = result_of(2);
  ASSERT_TRUE(r1 && r2);
  // a later batch has its own θs: the old one named by hash alone is missing now
  ASSERT_TRUE(send(peer, job_message(3, 41, nullptr, first)));
  const auto r3 = result_of(3);
  ASSERT_TRUE(r3);
  EXPECT_TRUE(r3->missing_theta());
  EXPECT_EQ(r3->results_size(), 0);
  expect_results_equal_run_task(*r1, first);
  expect_results_equal_run_task(*r2, second);
}

TEST_F(WorkerProcessTest, UnknownThetaHashGivesMissingTheta) {
  spawn();
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  const auto shared = std::make_shared<const std::vector<double>>(test_theta(9));
  ASSERT_TRUE(send(peer, job_message(5, 1, nullptr, {make_task(shared, "flat", 1, 50)})));
  const auto result = result_of(5);
  ASSERT_TRUE(result);
  EXPECT_TRUE(result->missing_theta());
  EXPECT_TRUE(contains(result->error(), "tasks[0].theta_hash")) << result->error();
  EXPECT_EQ(result->results_size(), 0);
  // the same job sent again with its θ runs
  const std::vector<RolloutTask> tasks = {make_task(shared, "flat", 1, 50)};
  ASSERT_TRUE(send(peer, job_message(6, 1, shared.get(), tasks)));
  const auto again = result_of(6);
  ASSERT_TRUE(again);
  expect_results_equal_run_task(*again, tasks);
}

TEST_F(WorkerProcessTest, GarbageFramesAreSurvived) {
  const pid_t pid = spawn();
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  RandomStream rng(stream_key(1, "garbage"));
  std::string noise(300, '\0');
  for (char& c : noise) c = static_cast<char>(rng.next_u64());
  const std::string frames[] = {
      noise,
      "",                              // a message with no kind
      std::string("\x9a\x06\x00", 3),  // a kind from a later protocol (field 99)
      job_message(7, 1, nullptr, {}).SerializeAsString().substr(0, 3) + "\xff\xff",  // truncated
      std::string(1 << 20, '\xff'),                                                  // a megabyte of nonsense
  };
  for (const std::string& frame : frames) ASSERT_TRUE(send_raw(peer, frame));
  // a message of two frames
  ASSERT_TRUE(router_->send(zmq::buffer(peer), zmq::send_flags::sndmore));
  ASSERT_TRUE(router_->send(zmq::str_buffer("one"), zmq::send_flags::sndmore));
  ASSERT_TRUE(router_->send(zmq::str_buffer("two"), zmq::send_flags::none));
  // a job whose task is wrong gets an error naming the field
  const std::vector<double> theta = test_theta(10);
  const auto shared = std::make_shared<const std::vector<double>>(theta);
  wire::CoordinatorMessage bad = job_message(8, 1, &theta, {make_task(shared, "flat", 1, 50)});
  bad.mutable_job()->mutable_tasks(0)->set_sigma(-1);
  bad.mutable_job()->mutable_tasks(0)->set_perturbation_key(3);
  bad.mutable_job()->mutable_tasks(0)->set_sign(1);
  ASSERT_TRUE(send(peer, bad));
  const auto refused = result_of(8);
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->error(), "tasks[0].sigma: must be in [0, 10]");
  // and it still runs a job
  const std::vector<RolloutTask> tasks = {make_task(shared, "r1", 2, 60)};
  ASSERT_TRUE(send(peer, job_message(9, 1, nullptr, tasks)));
  const auto result = result_of(9);
  ASSERT_TRUE(result);
  expect_results_equal_run_task(*result, tasks);
  EXPECT_EQ(children_.ended(pid), std::nullopt) << "the worker ended";
  EXPECT_TRUE(contains(err(), "dropped")) << err();
}

TEST_F(WorkerProcessTest, OversizedFrameCostsTheConnectionNotTheWorker) {
  const std::string huge((64 << 20) + 1, 'x');
  const pid_t pid = spawn();
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  // over the 64 MB cap: libzmq drops the connection; the worker finds the silence and says Hello again
  ASSERT_TRUE(send_raw(peer, huge));
  const std::string again = welcome_worker(10s);
  ASSERT_FALSE(again.empty());
  const auto shared = std::make_shared<const std::vector<double>>(test_theta(11));
  const std::vector<RolloutTask> tasks = {make_task(shared, "flat", 3, 40)};
  ASSERT_TRUE(send(again, job_message(1, 1, shared.get(), tasks)));
  const auto result = result_of(1);
  ASSERT_TRUE(result);
  expect_results_equal_run_task(*result, tasks);
  EXPECT_EQ(children_.ended(pid), std::nullopt);
  EXPECT_LE(rss_kb(pid), 50 * 1024);
}

TEST_F(WorkerProcessTest, RefusedExits2) {
  const pid_t pid = spawn();
  const auto hello = receive(wire::WorkerMessage::kHello, 10s);
  ASSERT_TRUE(hello) << err();
  wire::CoordinatorMessage refused;
  refused.mutable_refused()->set_reason("fingerprint 0123 differs from the coordinator's");
  ASSERT_TRUE(send(hello->peer, refused));
  EXPECT_EQ(wait_exit(pid, 5s), 2);
  EXPECT_TRUE(contains(err(), "fingerprint 0123 differs")) << err();
}

TEST_F(WorkerProcessTest, ShutdownExits0) {
  const pid_t pid = spawn();
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  wire::CoordinatorMessage shutdown;
  shutdown.mutable_shutdown()->set_reason("run finished");
  ASSERT_TRUE(send(peer, shutdown));
  EXPECT_EQ(wait_exit(pid, 5s), 0) << err();
}

TEST_F(WorkerProcessTest, ReconnectsWhenTheCoordinatorRestarts) {
  spawn();
  ASSERT_FALSE(welcome_worker().empty());
  ASSERT_TRUE(receive(wire::WorkerMessage::kHeartbeat, 2s));
  // the coordinator goes away and comes back on the same port
  const std::string endpoint = endpoint_;
  router_.reset();
  std::this_thread::sleep_for(200ms);
  bind(endpoint);
  const auto restarted = Clock::now();
  const std::string peer = welcome_worker(10s);
  ASSERT_FALSE(peer.empty());
  // silence for the liveness window (600 ms), a first backoff of 250 ms, then Hello at once
  EXPECT_LT(seconds_since(restarted), 2.5);
  const auto shared = std::make_shared<const std::vector<double>>(test_theta(12));
  const std::vector<RolloutTask> tasks = {make_task(shared, "r3", 4, 70)};
  ASSERT_TRUE(send(peer, job_message(1, 1, shared.get(), tasks)));
  const auto result = result_of(1);
  ASSERT_TRUE(result);
  expect_results_equal_run_task(*result, tasks);
  EXPECT_TRUE(contains(err(), "reconnecting")) << err();
}

TEST_F(WorkerProcessTest, SigtermDuringALongJobSaysGoodbyeAndExits0) {
  // twenty thousand episodes: many seconds of work on two threads (built first: the test answers no heartbeats
  // while it builds them)
  const auto shared = std::make_shared<const std::vector<double>>(test_theta(13));
  std::vector<RolloutTask> tasks;
  for (uint32_t i = 0; i < 20'000; ++i) tasks.push_back(make_task(shared, "flat", i, 2000));
  const wire::CoordinatorMessage job = job_message(1, 1, shared.get(), tasks);
  const pid_t pid = spawn();
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  ASSERT_TRUE(send(peer, job));
  // heartbeats keep coming while it runs
  heartbeats_.clear();
  const auto until = Clock::now() + 700ms;
  while (Clock::now() < until) {
    const auto r = receive(50ms);
    ASSERT_FALSE(r && r->message.has_result()) << "the long job ended already";
  }
  EXPECT_GE(heartbeats_[peer], 4);
  std::printf("worker RSS while a job runs: %ld kB\n", rss_kb(pid));

  const auto signalled = Clock::now();
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  const auto goodbye = receive(wire::WorkerMessage::kGoodbye, 2s);
  ASSERT_TRUE(goodbye) << err();
  EXPECT_EQ(goodbye->peer, peer);
  const int code = wait_exit(pid, 2s);
  EXPECT_EQ(code, 0) << err();
  EXPECT_LT(seconds_since(signalled), 2.0);
  std::printf("SIGTERM to exit: %.3f s\n", seconds_since(signalled));
}

TEST_F(WorkerProcessTest, CrashOnJobFaultDiesBySigabrtOnItsFirstJob) {
  // no core file for the deliberate abort
  rlimit saved{};
  ::getrlimit(RLIMIT_CORE, &saved);
  rlimit none = saved;
  none.rlim_cur = 0;
  ::setrlimit(RLIMIT_CORE, &none);
  const pid_t pid = spawn({"--fault", "crash-on-job"}, "worker", std::nullopt, POET_TEST_WORKER_BIN);
  ::setrlimit(RLIMIT_CORE, &saved);
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  // alive and heartbeating until a Job comes
  ASSERT_TRUE(receive(wire::WorkerMessage::kHeartbeat, 2s));
  const auto shared = std::make_shared<const std::vector<double>>(test_theta(14));
  ASSERT_TRUE(send(peer, job_message(1, 1, shared.get(), {make_task(shared, "flat", 1, 50)})));
  EXPECT_EQ(wait_exit(pid, 5s), 128 + SIGABRT) << err();
}

TEST_F(WorkerProcessTest, IgnoreJobsFaultHeartbeatsButNeverAnswers) {
  const pid_t pid = spawn({"--fault", "ignore-jobs"}, "worker", std::nullopt, POET_TEST_WORKER_BIN);
  const std::string peer = welcome_worker();
  ASSERT_FALSE(peer.empty());
  const auto shared = std::make_shared<const std::vector<double>>(test_theta(15));
  ASSERT_TRUE(send(peer, job_message(1, 1, shared.get(), {make_task(shared, "flat", 1, 20)})));
  heartbeats_.clear();
  const auto until = Clock::now() + 1s;
  while (Clock::now() < until) {
    const auto r = receive(50ms);
    ASSERT_FALSE(r && r->message.has_result());
  }
  EXPECT_GE(heartbeats_[peer], 7);
  EXPECT_EQ(children_.ended(pid), std::nullopt);
}

size_t count(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

TEST_F(WorkerProcessTest, UnreachableCoordinatorIsReportedAgainWithBackoff) {
  const poet::testing::LoopbackPort nobody(false);  // bound, so that nothing else takes the port, but not listening
  ASSERT_GT(nobody.port(), 0);
  const pid_t pid = spawn({}, "worker", nobody.endpoint());
  // no Welcome: a line after 2 s, then after gaps that double (6 s, 14 s, ... from the start)
  const auto deadline = Clock::now() + 12s;
  while (Clock::now() < deadline && count(err(), "still trying") < 2) std::this_thread::sleep_for(50ms);
  std::this_thread::sleep_until(deadline);  // and no third line before 14 s: the gaps grow
  const std::string log = err();
  EXPECT_EQ(count(log, "still trying"), 2u) << log;
  EXPECT_EQ(count(log, "still trying to reach the coordinator at " + nobody.endpoint()), 2u) << log;
  EXPECT_EQ(children_.ended(pid), std::nullopt) << "the worker keeps trying";
}

TEST_F(WorkerProcessTest, APeerSendingGarbageIsReportedAsSuch) {
  // a plain TCP server that answers every connection with bytes of another protocol, then hangs up
  const poet::testing::LoopbackPort server(true);
  ASSERT_GT(server.port(), 0);
  std::jthread garbage([fd = server.fd()](std::stop_token stop) {
    while (!stop.stop_requested()) {
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      const int client = ::accept4(fd, nullptr, nullptr, SOCK_CLOEXEC);
      if (client < 0) continue;
      constexpr char kReply[] = "HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n";
      (void)!::send(client, kReply, sizeof kReply - 1, MSG_NOSIGNAL);
      std::this_thread::sleep_for(300ms);
      ::close(client);
    }
  });
  const pid_t pid = spawn({}, "worker", server.endpoint());
  const auto deadline = Clock::now() + 10s;
  while (Clock::now() < deadline && !contains(err(), "ZeroMQ/poet protocol")) std::this_thread::sleep_for(50ms);
  const std::string log = err();
  EXPECT_TRUE(contains(log, "the peer at " + server.endpoint() + " does not speak the ZeroMQ/poet protocol")) << log;
  EXPECT_FALSE(contains(log, "CURVE")) << log;
  EXPECT_EQ(children_.ended(pid), std::nullopt) << "the worker keeps trying";
}

// The faults live in poet-test-worker only: poet-worker neither offers them in --help nor takes them.
TEST_F(WorkerProcessTest, TheProductionWorkerHasNoFaults) {
  const pid_t help = spawn_raw({POET_WORKER_BIN, "--help"}, "help");
  EXPECT_EQ(wait_exit(help, 10s), 0);
  const std::string text = read_file(root_ / "help.out");
  EXPECT_TRUE(contains(text, "--connect")) << text;
  for (const char* option : {"--fault", "--lie-after", "--lie-fraction", "--lie-where-predicted-unchecked"}) {
    EXPECT_FALSE(contains(text, option)) << option << " in\n" << text;
  }
  const std::vector<std::vector<std::string>> refused = {
      {"--fault", "wrong-results"}, {"--fault", "crash-on-job"},         {"--lie-after", "8"},
      {"--lie-fraction", "0.1"},    {"--lie-where-predicted-unchecked"},
  };
  for (size_t i = 0; i < refused.size(); ++i) {
    std::vector<std::string> args = {POET_WORKER_BIN, "--connect", endpoint_};
    args.insert(args.end(), refused[i].begin(), refused[i].end());
    const std::string name = "refused" + std::to_string(i);
    const pid_t pid = spawn_raw(args, name);
    EXPECT_EQ(wait_exit(pid, 10s), 2) << refused[i].front() << "\n" << err(name);
    EXPECT_TRUE(contains(err(name), "not expected: " + refused[i].back())) << err(name);
  }
  const pid_t test_help = spawn_raw({POET_TEST_WORKER_BIN, "--help"}, "test-help");
  EXPECT_EQ(wait_exit(test_help, 10s), 0);
  EXPECT_TRUE(contains(read_file(root_ / "test-help.out"), "--fault")) << "the test worker offers them";
}

TEST_F(WorkerProcessTest, BadCommandLinesExit2AndFingerprintMatchesThisBuild) {
  const std::vector<std::vector<std::string>> bad = {
      {POET_WORKER_BIN},
      {POET_WORKER_BIN, "--connect", "localhost:5555"},
      {POET_WORKER_BIN, "--connect", "tcp://localhost:99999"},
      {POET_WORKER_BIN, "--connect", endpoint_, "--threads", "0"},
      {POET_TEST_WORKER_BIN, "--connect", endpoint_, "--fault", "explode"},
      {POET_WORKER_BIN, "--connect", endpoint_, "--log-level", "loud"},
      {POET_WORKER_BIN, "--connect", endpoint_, "--no-such-flag"},
  };
  for (size_t i = 0; i < bad.size(); ++i) {
    const std::string name = "bad" + std::to_string(i);
    const pid_t pid = spawn_raw(bad[i], name);
    EXPECT_EQ(wait_exit(pid, 10s), 2) << bad[i].back() << "\n" << err(name);
  }
  const pid_t pid = spawn_raw({POET_WORKER_BIN, "--fingerprint"}, "fingerprint");
  EXPECT_EQ(wait_exit(pid, 10s), 0);
  EXPECT_EQ(read_file(root_ / "fingerprint.out"), build_fingerprint());
}

}  // namespace
}  // namespace poet
