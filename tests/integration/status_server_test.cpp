// Tests coordinator/status/status_server.cpp over real loopback sockets: a StatusServer on an ephemeral port in
// this process, fed a hand-made run, asked by a real HTTP client (every endpoint, the 404/405/400 rules), by raw
// TCP (garbage request lines, oversized requests, slow clients that send half a request and sit, 200 slowloris
// clients on either port while the other clients are answered, the oldest connections shed past a cap, requests on
// a kept-alive connection), and by poetctl run as a real process. Every wait is bounded; TearDown closes every socket,
// kills every child, stops the server and removes the directory, even when a test fails.

#include "coordinator/status/status_server.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"
#include "common/program/build_fingerprint.h"
#include "coordinator/status/status_board.h"
#include "engine/run_state.h"
#include "loopback_port.h"
#include "poetctl_child.h"
#include "raw_client.h"
#include "run_directory/files/run_directory.h"
#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using nlohmann::json;
using poet::testing::connect_to;
using poet::testing::contains;
using poet::testing::read_file;
using poet::testing::receive;
using poet::testing::Received;
using poet::testing::send_all;
using Clock = std::chrono::steady_clock;

constexpr auto kReadTimeout = 1000ms;  // the server's, in these tests
constexpr auto kMargin = 3s;           // what a loaded machine may add to a bound

// A run at iteration 5: pair 0 retired, pair 1 its child (solved), pair 2 child of 1 with a transfer from 0.
RunState demo_state() {
  // by hand: engine/engine.h brings Eigen, whose parameter names <resolv.h> (in httplib.h) defines as a macro
  RunState state;
  state.settings.seed = 7;
  state.settings.iterations = 100;
  state.pairs.emplace_back();
  state.next_iteration = 5;
  state.counters.rollouts = 1234;
  state.counters.env_steps = 98765;
  state.pairs[0].retired_iteration = 4;
  for (int id : {1, 2}) {
    Pair pair;
    pair.id = id;
    pair.env = state.pairs[0].env;
    pair.env.encoding.roughness = id;
    pair.env.encoding.name = "rough-" + std::to_string(id);
    pair.parent_id = id - 1;
    pair.created_iteration = id + 1;
    pair.latest_score = 100.0 * id;
    pair.best_score = 100.0 * id + 5;
    state.pairs.push_back(pair);
  }
  state.pairs[1].first_solved_iteration = 3;
  state.pairs[2].transfers = {{4, 0, true, 150.0}};
  state.next_pair_id = 3;
  return state;
}

using Outcome = poet::testing::ChildOutcome;

class StatusServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // an HTTP client writing to a server that hung up must fail, not kill the test binary
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    ::sigaction(SIGPIPE, &ignore, &old_sigpipe_);

    fs::create_directories(root_ / "run");
    std::ofstream(root_ / "run" / kEventsFile) << "{\"iteration\":0,\"event\":\"pair_created\",\"pair\":0}\n"
                                               << "{\"iteration\":3,\"event\":\"solved\",\"pair\":1}\n"
                                               << "{\"iteration\":4,\"event\":\"transfer\",\"target\":2}\n";
    std::ofstream stats(root_ / "run" / kStatsFile);
    stats << pair_stats_header();
    for (int t = 0; t < 5; ++t) {
      PairStatsRow row;
      row.iteration = t;
      row.pair = 2;
      row.score = 10.0 * t;
      row.best_score = 10.0 * t;
      stats << pair_stats_row(row);
    }
    stats.close();

    board_ = std::make_unique<StatusBoard>(root_ / "run");
    board_->publish_run(demo_state(), 5);
    WorkerView worker;
    worker.id = "w-1";
    worker.name = "10.1.2.3";
    worker.threads = 2;
    worker.fingerprint_digest = 0x1234;
    worker.jobs_done = 40;
    worker.results_done = 38;
    worker.last_heard = 750;
    board_->publish_dispatch({.workers = {worker},
                              .refused = {},
                              .at = 1'000,
                              .queue_depth = 6,
                              .in_flight_jobs = 2,
                              .dropped_frames = {{"malformed", 1}}});
    board_->set_state(RunPhase::kRunning);
    server_ = std::make_unique<StatusServer>(*board_, options());
    const Expected<int> port = server_->start("127.0.0.1:0");
    ASSERT_TRUE(port) << port.error();
    port_ = *port;
    ASSERT_GT(port_, 0);
  }

  void TearDown() override {
    children_.kill_all();
    for (int fd : sockets_) ::close(fd);
    if (server_) server_->stop();
    server_.reset();
    board_.reset();
    ::sigaction(SIGPIPE, &old_sigpipe_, nullptr);
  }

  static StatusServerOptions options() {
    StatusServerOptions o;
    o.threads = 2;
    o.idle_timeout = std::chrono::duration_cast<std::chrono::seconds>(kReadTimeout);
    return o;
  }

  std::unique_ptr<httplib::Client> client() {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", port_);
    c->set_connection_timeout(2, 0);
    c->set_read_timeout(10, 0);
    c->set_write_timeout(10, 0);
    return c;
  }

  // A raw connection to the server, closed in TearDown.
  int raw() {
    const int fd = connect_to(port_);
    EXPECT_GE(fd, 0) << "connect to 127.0.0.1:" << port_;
    if (fd >= 0) sockets_.push_back(fd);
    return fd;
  }

  // Sends bytes on a fresh connection and returns the response that comes back (bounded).
  std::string exchange(std::string_view request) {
    const int fd = raw();
    if (fd < 0) return "";
    EXPECT_TRUE(send_all(fd, request));
    std::string response =
        receive(fd, std::chrono::duration_cast<std::chrono::milliseconds>(kReadTimeout + kMargin), true).data;
    std::erase(sockets_, fd);  // hang up, so that the server's thread is free for the next one
    ::close(fd);
    return response;
  }

  Outcome poetctl(const std::vector<std::string>& args, const std::string& name,
                  const std::vector<std::string>& extra_env = {}) {
    return poet::testing::run_poetctl(children_, root_, args, name, extra_env);
  }

  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }

  // the children go first, the directory after them
  poet::testing::ScratchDir scratch_{"poet_status_server_test"};
  fs::path root_ = scratch_.path();
  std::unique_ptr<StatusBoard> board_;
  std::unique_ptr<StatusServer> server_;
  int port_ = 0;
  std::vector<int> sockets_;
  poet::testing::Children children_;
  struct sigaction old_sigpipe_ {};
};

TEST_F(StatusServerTest, EveryEndpointAnswersWithJson) {
  auto http = client();
  for (const char* path :
       {"/status", "/pairs", "/pairs/0", "/pairs/2", "/archive", "/workers", "/events", "/events?since=1&limit=1"}) {
    const httplib::Result r = http->Get(path);
    ASSERT_TRUE(r) << path << ": " << httplib::to_string(r.error());
    EXPECT_EQ(r->status, 200) << path << " " << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/json") << path;
    EXPECT_TRUE(json::accept(r->body)) << path << ": " << r->body;
  }
  const json status = json::parse(http->Get("/status")->body);
  EXPECT_EQ(status["iteration"], 5);
  EXPECT_EQ(status["pairs_created"], 3);
  EXPECT_EQ(status["pairs_active"], 2);
  EXPECT_EQ(status["workers"], 1);
  EXPECT_EQ(status["state"], "running");
  EXPECT_EQ(status["rollouts"], "1234");
  const json pair = json::parse(http->Get("/pairs/2")->body);
  EXPECT_EQ(pair["lineage"]["ancestors"], json::array({1, 0}));
  EXPECT_EQ(pair["scores"].size(), 5u);
  const json events = json::parse(http->Get("/events?since=1&limit=1")->body);
  EXPECT_EQ(events["events"][0]["event"], "solved");
  EXPECT_EQ(events["next"], "2");
  EXPECT_EQ(json::parse(http->Get("/workers")->body)["workers"][0]["address"], "10.1.2.3");

  const httplib::Result metrics = http->Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->status, 200);
  EXPECT_TRUE(metrics->get_header_value("Content-Type").starts_with("text/plain; version=0.0.4"));
  EXPECT_TRUE(contains(metrics->body, "\npoet_iteration 5\n")) << metrics->body;
  EXPECT_TRUE(contains(metrics->body, "poet_dropped_frames_total{reason=\"malformed\"} 1\n")) << metrics->body;
  const httplib::Result health = http->Get("/healthz");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
  EXPECT_TRUE(contains(health->body, R"("ok":true)")) << health->body;
  EXPECT_TRUE(health->get_header_value("Content-Type").starts_with("application/json"));
  const httplib::Result head = http->Head("/status");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  EXPECT_TRUE(head->body.empty());
}

TEST_F(StatusServerTest, ErrorsHaveTheirStatusAndAJsonBody) {
  auto http = client();
  auto check = [](const httplib::Result& r, int status, const std::string& what) {
    ASSERT_TRUE(r) << what;
    EXPECT_EQ(r->status, status) << what << ": " << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/json") << what;
    ASSERT_TRUE(json::accept(r->body)) << what << ": " << r->body;
    EXPECT_EQ(json::parse(r->body)["status"], status) << what;
  };
  check(http->Get("/nope"), 404, "GET /nope");
  check(http->Get("/pairs/99"), 404, "GET /pairs/99");
  check(http->Get("/pairs/abc"), 404, "GET /pairs/abc");
  check(http->Get("/events?since=abc"), 400, "since=abc");
  check(http->Get("/events?since=-3"), 400, "since=-3");
  const httplib::Result post = http->Post("/status", "{}", "application/json");
  check(post, 405, "POST /status");
  EXPECT_EQ(post->get_header_value("Allow"), "GET, HEAD");
  const httplib::Result del = http->Delete("/pairs/1");
  check(del, 405, "DELETE /pairs/1");
  EXPECT_EQ(del->get_header_value("Allow"), "GET, HEAD");
  check(http->Post("/nope", "", "text/plain"), 404, "POST /nope");
  // a POST without a body (curl -X POST) is answered at once, not read to the end of the connection
  const auto started = Clock::now();
  const std::string bodyless = exchange("POST /status HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_TRUE(bodyless.starts_with("HTTP/1.1 405")) << bodyless;
  EXPECT_TRUE(contains(bodyless, "Allow: GET, HEAD")) << bodyless;
  EXPECT_LT(Clock::now() - started, kReadTimeout);
  EXPECT_TRUE(exchange("TRACE /status HTTP/1.1\r\nHost: x\r\n\r\n").starts_with("HTTP/1.1 405"));
}

// A request line the server cannot parse is refused by libmicrohttpd itself, before any route: a 400 of its own
// (an HTML body) or, for a line with no space in it, the connection closed (libmicrohttpd 0.9.75 leaves no way to
// answer it). Either way nothing else is disturbed.
TEST_F(StatusServerTest, MalformedRequestsGet400AndTheServerGoesOn) {
  for (const std::string& garbage : {std::string("garbage\r\n\r\n"), std::string("\x01\x02\xff\xfe junk\r\n\r\n"),
                                     std::string("GET\r\n\r\n"), std::string("GET /status\r\n\r\n")}) {
    const std::string answer = exchange(garbage);
    EXPECT_TRUE(answer.empty() || answer.starts_with("HTTP/1.1 400")) << json(garbage).dump() << " -> " << answer;
  }
  // a URI beyond 8 KB, a body beyond the limit
  EXPECT_TRUE(exchange("GET /" + std::string(20000, 'a') + " HTTP/1.1\r\nHost: x\r\n\r\n").starts_with("HTTP/1.1 414"));
  EXPECT_TRUE(
      exchange("POST /status HTTP/1.1\r\nHost: x\r\nContent-Length: 10000000\r\n\r\n").starts_with("HTTP/1.1 413"));
  // and it still answers
  const httplib::Result r = client()->Get("/healthz");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
}

// libmicrohttpd keeps each query parameter in the connection's memory pool and closes the connection unanswered
// when a few hundred fill it: a query past 64 parameters gets a 400, one past 8 KB a 414, each with its JSON body.
TEST_F(StatusServerTest, QueriesWithTooManyParametersGetAnAnswer) {
  std::string many;
  for (int i = 0; i < 500; ++i) many += "a=1&";
  const std::string too_many = exchange("GET /status?" + many + " HTTP/1.1\r\nHost: x\r\n\r\n");
  ASSERT_TRUE(too_many.starts_with("HTTP/1.1 400")) << too_many.substr(0, 300);
  EXPECT_TRUE(contains(too_many, "too many query parameters (at most 64)")) << too_many;
  EXPECT_TRUE(contains(too_many, "application/json")) << too_many;
  // past 8 KB of parameters, and of separators alone (each an empty parameter)
  for (const std::string& query : {many + many + many + many + many, std::string(9000, '&')}) {
    const std::string long_uri = exchange("GET /events?" + query + " HTTP/1.1\r\nHost: x\r\n\r\n");
    EXPECT_TRUE(long_uri.starts_with("HTTP/1.1 414")) << long_uri.substr(0, 300);
    EXPECT_TRUE(contains(long_uri, "request URI too long")) << long_uri.substr(0, 300);
  }
  // 64 parameters are still a request like any other, and the server goes on
  std::string enough = "since=0";
  for (int i = 1; i < 64; ++i) enough += "&x" + std::to_string(i) + "=1";
  EXPECT_TRUE(exchange("GET /events?" + enough + " HTTP/1.1\r\nHost: x\r\n\r\n").starts_with("HTTP/1.1 200"));
  const httplib::Result r = client()->Get("/healthz");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
}

TEST_F(StatusServerTest, KeptAliveRequestsAreAnsweredAtOnce) {
  // a response written in two pieces (headers, body) waits for the client's delayed ACK (40 ms on Linux) unless
  // the server sets TCP_NODELAY; the first request escapes it (a new connection ACKs at once), the rest do not
  const int fd = raw();
  ASSERT_GE(fd, 0);
  std::vector<double> ms;
  for (int i = 0; i < 10; ++i) {
    const auto started = Clock::now();
    ASSERT_TRUE(send_all(fd, "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n"));
    const Received r = receive(fd, std::chrono::duration_cast<std::chrono::milliseconds>(kReadTimeout), true);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - started).count());
    ASSERT_TRUE(r.data.starts_with("HTTP/1.1 200")) << "request " << i << ": " << r.data;
    ASSERT_FALSE(r.closed) << "request " << i << ": the connection was not kept alive";
  }
  // the median: one request slowed by a loaded machine is not the delay this is about
  std::vector<double> sorted = ms;
  std::nth_element(sorted.begin(), sorted.begin() + 5, sorted.end());
  EXPECT_LT(sorted[5], 20.0) << "ms per request: " << ::testing::PrintToString(ms);
}

TEST_F(StatusServerTest, ASlowClientDoesNotStopOthers) {
  // one client sends half a request and sits; the other pool thread answers at once
  const int slow = raw();
  ASSERT_GE(slow, 0);
  ASSERT_TRUE(send_all(slow, "GET /status HTTP/1.1\r\nHost: x\r\n"));
  std::this_thread::sleep_for(50ms);  // so that the server has taken it
  const auto started = Clock::now();
  const httplib::Result r = client()->Get("/status");
  const auto took = Clock::now() - started;
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_LT(took, kReadTimeout) << "served only after the slow client timed out";

  // the slow client is dropped after the read timeout
  const Received rest = receive(slow, std::chrono::duration_cast<std::chrono::milliseconds>(kReadTimeout + kMargin));
  EXPECT_TRUE(rest.closed);
}

TEST_F(StatusServerTest, MoreSlowClientsThanThreadsDelayNoOneAndAreClosedWhenIdle) {
  std::vector<int> slow;
  for (int i = 0; i < options().threads + 1; ++i) {
    slow.push_back(raw());
    ASSERT_GE(slow.back(), 0);
    ASSERT_TRUE(send_all(slow.back(), "GET /status HTTP/1.1\r\nHo"));
  }
  std::this_thread::sleep_for(50ms);
  const auto started = Clock::now();
  const httplib::Result r = client()->Get("/status");
  ASSERT_TRUE(r) << httplib::to_string(r.error());
  EXPECT_EQ(r->status, 200);
  EXPECT_LT(Clock::now() - started, kReadTimeout) << "a slow client holds no thread";
  for (int fd : slow)
    EXPECT_TRUE(receive(fd, std::chrono::duration_cast<std::chrono::milliseconds>(kReadTimeout + kMargin)).closed);
}

// With 200 slowloris clients on either port, /status on the status socket (the coordinator's options) and /healthz
// on the probes' listener each answer within a second, for longer than the idle timeout; the clients are kept, but
// for those past the listener's cap for one address, which are shed.
TEST_F(StatusServerTest, SlowClientsOnEitherPortDelayNoAnswer) {
  StatusServer status(*board_);
  StatusServer health(*board_, health_listener_options());
  const Expected<int> status_port = status.start("127.0.0.1:0");
  const Expected<int> health_port = health.start("127.0.0.1:0");
  ASSERT_TRUE(status_port) << status_port.error();
  ASSERT_TRUE(health_port) << health_port.error();
  for (const auto& [port, path] : {std::pair{*status_port, "/status"}, std::pair{*health_port, "/healthz"}}) {
    const poet::testing::SlowClients slow(port, 200);
    std::this_thread::sleep_for(500ms);  // so that the server has taken them
    httplib::Client client("127.0.0.1", port);
    client.set_connection_timeout(1, 0);  // kubelet's default probe timeout
    client.set_read_timeout(1, 0);
    for (int i = 0; i < 8; ++i) {  // over 4 s: past both idle timeouts
      const auto started = Clock::now();
      const httplib::Result r = client.Get(path);
      ASSERT_TRUE(r) << path << " " << i << ": " << httplib::to_string(r.error());
      EXPECT_EQ(r->status, 200) << path;
      EXPECT_LT(Clock::now() - started, 1s) << path << " " << i;
      std::this_thread::sleep_for(500ms);
    }
    // clients that keep sending are kept, up to the listener's cap for one address (the probes' listener's is 64)
    const ConnectionCaps caps = port == *status_port ? StatusServerOptions{}.caps : health_listener_options().caps;
    const int kept = slow.size() - slow.closed();
    EXPECT_LE(kept, std::min<int>(slow.size(), static_cast<int>(caps.per_address))) << path;
    EXPECT_GE(kept, std::min<int>(slow.size(), static_cast<int>(caps.per_address) - 2)) << path;
  }
  // the listener serves the probes and nothing else
  httplib::Client probe("127.0.0.1", *health_port);
  const httplib::Result other = probe.Get("/status");
  ASSERT_TRUE(other);
  EXPECT_EQ(other->status, 404);
}

// Past a cap a new connection sheds the oldest: of its own address past the address's cap, else of all; the new one
// is answered at once, and the connections not shed stay open.
TEST_F(StatusServerTest, ANewConnectionPastACapShedsTheOldest) {
  StatusServerOptions small = options();
  small.caps = {.total = 5, .per_address = 3};
  small.idle_timeout = 30s;  // whatever closes a connection here is the shedding
  StatusServer server(*board_, small);
  const Expected<int> port = server.start("127.0.0.1:0");
  ASSERT_TRUE(port) << port.error();
  auto slow = [&](const char* source) {
    const int fd = connect_to(*port, source);
    EXPECT_GE(fd, 0) << source;
    if (fd >= 0) sockets_.push_back(fd);
    EXPECT_TRUE(send_all(fd, "GET /status HTTP/1.1\r\n"));
    std::this_thread::sleep_for(20ms);  // taken in this order
    return fd;
  };
  auto shed = [](int fd) { return receive(fd, 1000ms).closed; };
  const std::vector<int> a = {slow("127.0.0.2"), slow("127.0.0.2"), slow("127.0.0.2")};
  const int a4 = slow("127.0.0.2");  // past 127.0.0.2's cap: its oldest goes
  EXPECT_TRUE(shed(a[0]));
  const std::vector<int> b = {slow("127.0.0.3"), slow("127.0.0.3")};
  const int c = slow("127.0.0.4");  // past the total: the oldest of all goes
  EXPECT_TRUE(shed(a[1]));
  // a probe past the total is answered at once, shedding the next oldest
  const int probe = connect_to(*port, "127.0.0.5");
  ASSERT_GE(probe, 0);
  sockets_.push_back(probe);
  const auto started = Clock::now();
  ASSERT_TRUE(send_all(probe, "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n"));
  const Received answer = receive(probe, 1000ms, true);
  EXPECT_TRUE(answer.data.starts_with("HTTP/1.1 200")) << answer.data;
  EXPECT_LT(Clock::now() - started, 100ms);
  EXPECT_TRUE(shed(a[2]));
  for (int fd : {a4, b[0], b[1], c}) EXPECT_FALSE(poet::testing::closed_by_peer(fd)) << "a newer one was shed";
  for (int fd : sockets_) ::close(fd);  // so that stop need not wait for them
  sockets_.clear();
  server.stop();
}

TEST_F(StatusServerTest, StopIsBoundedAndTheServerStartsAgain) {
  // a second server cannot take the same port, and says which address
  StatusServer other(*board_);
  const Expected<int> taken = other.start(address());
  ASSERT_FALSE(taken);
  EXPECT_TRUE(contains(taken.error(), address())) << taken.error();
  EXPECT_FALSE(other.start("nonsense"));
  EXPECT_FALSE(other.start("127.0.0.1:70000"));
  const Expected<int> twice = server_->start("127.0.0.1:0");
  EXPECT_FALSE(twice);

  // stop with a slow client connected: bounded by the read timeout
  const int slow = raw();
  ASSERT_GE(slow, 0);
  ASSERT_TRUE(send_all(slow, "GET /status HTTP/1.1\r\n"));
  std::this_thread::sleep_for(50ms);
  const auto started = Clock::now();
  server_->stop();
  EXPECT_LT(Clock::now() - started, kReadTimeout + kMargin);
  EXPECT_EQ(server_->port(), 0);
  EXPECT_EQ(connect_to(port_), -1) << "nothing listens after stop";

  const Expected<int> again = server_->start("127.0.0.1:0");
  ASSERT_TRUE(again) << again.error();
  port_ = *again;
  const httplib::Result r = client()->Get("/healthz");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  server_->stop();
  server_->stop();  // idempotent
}

TEST_F(StatusServerTest, PoetctlPrintsTheRun) {
  const Outcome status = poetctl({"--address", address(), "status"}, "status");
  EXPECT_EQ(status.code, 0) << status.err;
  EXPECT_TRUE(contains(status.out, "iteration   5 of 100")) << status.out;
  EXPECT_TRUE(contains(status.out, "3 created, 2 active, 1 solved")) << status.out;
  EXPECT_TRUE(contains(status.out, "state       running")) << status.out;
  EXPECT_TRUE(contains(status.out, "rollouts    1234")) << status.out;
  EXPECT_TRUE(contains(status.out, "ANNECS      1 at admission, 0 at archiving")) << status.out;
  EXPECT_TRUE(contains(status.out,
                       "frontier    roughness 1.0, gap top 0.0, stump top 0.0 solved (2.0, 0.0, 0.0 admitted); hardest "
                       "level solved: easy"))
      << status.out;

  const Outcome pairs = poetctl({"--address", address(), "pairs"}, "pairs");
  EXPECT_EQ(pairs.code, 0) << pairs.err;
  EXPECT_TRUE(contains(pairs.out, "rough-1")) << pairs.out;
  EXPECT_TRUE(contains(pairs.out, "retired@4")) << pairs.out;
  EXPECT_TRUE(contains(pairs.out, "3 pairs")) << pairs.out;

  const Outcome workers = poetctl({"workers", "--json", "--address", address()}, "workers");
  EXPECT_EQ(workers.code, 0) << workers.err;
  ASSERT_TRUE(json::accept(workers.out)) << workers.out;
  const json w = json::parse(workers.out);
  ASSERT_EQ(w["workers"].size(), 1u);
  EXPECT_EQ(w["workers"][0]["id"], "w-1");
  EXPECT_EQ(w["queue_depth"], "6");

  const Outcome pair = poetctl({"--address", address(), "pair", "2"}, "pair");
  EXPECT_EQ(pair.code, 0) << pair.err;
  EXPECT_TRUE(contains(pair.out, "ancestors   1 <- 0")) << pair.out;
  EXPECT_TRUE(contains(pair.out, "iteration 4 from pair 0 (proposal)")) << pair.out;

  const Outcome events = poetctl({"--address", address(), "events", "--since", "1"}, "events");
  EXPECT_EQ(events.code, 0) << events.err;
  EXPECT_TRUE(contains(events.out, "iteration 3: solved pair=1")) << events.out;
  EXPECT_FALSE(contains(events.out, "pair_created")) << events.out;

  const Outcome metrics = poetctl({"--address", address(), "metrics"}, "metrics");
  EXPECT_EQ(metrics.code, 0) << metrics.err;
  EXPECT_TRUE(contains(metrics.out, "poet_iteration 5\n")) << metrics.out;

  // the address from the environment
  const Outcome from_env = poetctl({"status"}, "env", {"POET_STATUS=" + address()});
  EXPECT_EQ(from_env.code, 0) << from_env.err;
  EXPECT_TRUE(contains(from_env.out, "iteration   5 of 100")) << from_env.out;
}

TEST_F(StatusServerTest, PoetctlFailuresHaveTheirExitCodes) {
  // a port where nothing listens: bound (so nobody else takes it) but not listening
  const poet::testing::LoopbackPort holder(false);
  ASSERT_GT(holder.port(), 0);
  const std::string closed = holder.address();

  const Outcome unreachable = poetctl({"--address", closed, "status"}, "closed");
  EXPECT_EQ(unreachable.code, 1) << unreachable.out << unreachable.err;
  EXPECT_TRUE(contains(unreachable.err, closed)) << unreachable.err;
  const Outcome unreachable_env = poetctl({"pairs"}, "closed_env", {"POET_STATUS=" + closed});
  EXPECT_EQ(unreachable_env.code, 1);
  EXPECT_TRUE(contains(unreachable_env.err, closed)) << unreachable_env.err;

  const Outcome no_pair = poetctl({"--address", address(), "pair", "99"}, "no_pair");
  EXPECT_EQ(no_pair.code, 1);
  EXPECT_TRUE(contains(no_pair.err, "no pair 99")) << no_pair.err;

  for (const auto& [args, name] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{}, "none"},
           {{"frobnicate"}, "unknown"},
           {{"pair"}, "no_id"},
           {{"pair", "x"}, "bad_id"},
           {{"events", "--since", "-1"}, "bad_since"},
           {{"--address", "nonsense", "status"}, "bad_address"},
           {{"--address", "127.0.0.1:99999", "status"}, "bad_port"}}) {
    const Outcome o = poetctl(args, name);
    EXPECT_EQ(o.code, 2) << name << ": " << o.err;
    EXPECT_FALSE(o.err.empty()) << name;
  }
  const Outcome fingerprint = poetctl({"--fingerprint"}, "fingerprint");
  EXPECT_EQ(fingerprint.code, 0);
  EXPECT_EQ(fingerprint.out, build_fingerprint());  // the same text as every other binary of the build

  const Outcome help = poetctl({"--help"}, "help");
  EXPECT_EQ(help.code, 0);
  EXPECT_TRUE(contains(help.out, "127.0.0.1:8580")) << help.out;
  EXPECT_TRUE(contains(help.out, "POET_STATUS")) << help.out;
}

}  // namespace
}  // namespace poet
