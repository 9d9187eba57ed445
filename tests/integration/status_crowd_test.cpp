// Tests poet-coordinator's status socket and probes' listener (--health-address) under crowds, as a real process
// over real sockets: 1,100 slowloris connections on each port from 20 loopback addresses (55 an address, under
// every per-address cap), then /status and /healthz asked on fresh connections from an address of the crowd's and
// from one with no slow connection, each answer due within 100 ms; past its caps a listener sheds the oldest
// connections and keeps the rest. Once as the coordinator starts here, once under a hard descriptor limit of 1024
// (prlimit), where it fits its caps into the limit and says so. The coordinator waits for workers that never come,
// so it uses no CPU; this process raises its own descriptor limit for the crowd. Every wait is bounded; the fixture
// kills the coordinator and removes its directory, and the crowd's sockets close with the test.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "coordinator/status/status_server.h"
#include "coordinator_run_fixture.h"
#include "raw_client.h"

namespace poet::testing {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kCrowd = 1100;         // slow connections on each port
constexpr int kCrowdAddresses = 20;  // 127.0.0.2 ... 127.0.0.21: 55 connections each
constexpr double kPromptMs = 100;    // the bound on each probe's whole answer
constexpr int kRounds = 5;           // probes of each kind

class StatusCrowdTest : public CoordinatorRunTest {
 protected:
  void SetUp() override {
    CoordinatorRunTest::SetUp();
    // the crowds' sockets are this process's: 2,200 of them and the probes'
    ::getrlimit(RLIMIT_NOFILE, &saved_limit_);
    rlimit raised = saved_limit_;
    raised.rlim_cur = saved_limit_.rlim_max;
    ::setrlimit(RLIMIT_NOFILE, &raised);
    if (raised.rlim_cur < 4096) GTEST_SKIP() << "the hard RLIMIT_NOFILE (" << raised.rlim_cur << ") is below 4096";
  }
  void TearDown() override { ::setrlimit(RLIMIT_NOFILE, &saved_limit_); }

  struct Ports {
    pid_t pid = -1;
    int status = 0;
    int health = 0;
  };

  // A coordinator that waits for workers (none come), its status socket and probes' listener on ephemeral ports;
  // launcher, when given, is the command line that runs it (prlimit ...).
  Ports start(const std::string& name, std::vector<std::string> launcher = {}) {
    std::vector<std::string> args = std::move(launcher);
    args.insert(args.end(), {POET_COORDINATOR_BIN, "--config", config_.string(), "--run-dir", (root_ / name).string(),
                             "--quiet", "--listen", "tcp://127.0.0.1:*", "--status-address", "127.0.0.1:0",
                             "--health-address", "127.0.0.1:0"});
    Ports ports;
    ports.pid = children_.start(std::move(args), root_ / name);
    ports.status = std::atoi(await_log(name, R"(status: http://127\.0\.0\.1:(\d+)/status)").c_str());
    ports.health = std::atoi(await_log(name, R"(health: http://127\.0\.0\.1:(\d+)/healthz)").c_str());
    return ports;
  }

  // One GET on a fresh connection from source: the milliseconds to its whole 200 answer, or -1 when it failed.
  static double probe(int port, const std::string& path, const char* source) {
    const auto started = Clock::now();
    const int fd = connect_to(port, source);
    if (fd < 0) return -1;
    const bool sent = send_all(fd, "GET " + path + " HTTP/1.1\r\nHost: x\r\n\r\n");
    const Received r = receive(fd, 2000ms, true);
    ::close(fd);
    if (!sent || !r.data.starts_with("HTTP/1.1 200") || !whole_response(r.data)) return -1;
    return std::chrono::duration<double, std::milli>(Clock::now() - started).count();
  }

  // kRounds rounds of /status and /healthz from an address of the crowd's and from one with none: every answer
  // whole and within kPromptMs.
  static void expect_prompt_answers(const Ports& ports) {
    for (int round = 0; round < kRounds; ++round) {
      for (const char* source : {"127.0.0.1", "127.0.0.2"}) {
        for (const auto& [port, path] : {std::pair{ports.status, "/status"}, std::pair{ports.health, "/healthz"}}) {
          const double ms = probe(port, path, source);
          EXPECT_GE(ms, 0) << path << " from " << source << ", round " << round << ": no answer";
          EXPECT_LT(ms, kPromptMs) << path << " from " << source << ", round " << round;
        }
      }
      std::this_thread::sleep_for(100ms);
    }
  }

  // The crowd on a listener with these caps: those past the caps shed, the rest kept (the probes shed a few more).
  static void expect_shed_to(const SlowClients& crowd, const ConnectionCaps& caps, const char* what) {
    const int cap = static_cast<int>(std::min<size_t>(caps.total, caps.per_address * kCrowdAddresses));
    const int kept = crowd.size() - crowd.closed();
    EXPECT_LE(kept, cap) << what;
    EXPECT_GE(kept, cap - 2 * kRounds - 1) << what << ": more were shed than the caps ask";
  }

  rlimit saved_limit_{};
};

// As it starts here (its soft descriptor limit raised to the hard one): the defaults' caps, every probe prompt.
TEST_F(StatusCrowdTest, CrowdsOnBothPortsKeepNoProbeOut) {
  const Ports ports = start("crowd");
  ASSERT_GT(ports.status, 0);
  ASSERT_GT(ports.health, 0);
  const SlowClients on_status(ports.status, kCrowd, kCrowdAddresses);
  const SlowClients on_health(ports.health, kCrowd, kCrowdAddresses);
  ASSERT_EQ(on_status.size(), kCrowd);
  ASSERT_EQ(on_health.size(), kCrowd);
  std::this_thread::sleep_for(500ms);  // so that the servers have taken them
  expect_prompt_answers(ports);
  // past both idle timeouts (the crowd keeps sending): only the shedding has closed any
  std::this_thread::sleep_for(3500ms);
  expect_shed_to(on_status, StatusServerOptions{}.caps, "status socket");
  expect_shed_to(on_health, health_listener_options().caps, "health listener");
  EXPECT_FALSE(children_.ended(ports.pid).has_value()) << read(root_ / "crowd.err");
}

// Under a hard limit of 1024 descriptors, where the defaults' caps would take them all: the coordinator fits its
// listeners into half of it, warns, and answers every probe as promptly, the run keeping its descriptors.
TEST_F(StatusCrowdTest, UnderAHardLimitOf1024TheCapsShrinkAndProbesStillAnswer) {
  if (::access("/usr/bin/prlimit", X_OK) != 0) GTEST_SKIP() << "no /usr/bin/prlimit (util-linux)";
  const Ports ports = start("limited", {"/usr/bin/prlimit", "--nofile=1024:1024", "--"});
  ASSERT_GT(ports.status, 0);
  ASSERT_GT(ports.health, 0);
  EXPECT_TRUE(contains(read(root_ / "limited.err"), "this process may open 1024 file descriptors"))
      << read(root_ / "limited.err");
  StatusServerOptions status;
  StatusServerOptions health = health_listener_options();
  ASSERT_TRUE(fit_listeners(1024, status, health));
  const SlowClients on_status(ports.status, kCrowd, kCrowdAddresses);
  const SlowClients on_health(ports.health, kCrowd, kCrowdAddresses);
  std::this_thread::sleep_for(500ms);
  expect_prompt_answers(ports);
  std::this_thread::sleep_for(3500ms);
  expect_shed_to(on_status, status.caps, "status socket");
  expect_shed_to(on_health, health.caps, "health listener");
  EXPECT_FALSE(children_.ended(ports.pid).has_value()) << read(root_ / "limited.err");
}

}  // namespace
}  // namespace poet::testing
