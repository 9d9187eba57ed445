// The coordinator's job socket under attack, with real processes and a rogue ZeroMQ peer on loopback: garbage,
// truncated, multi-part, oversized, wrong-version and wrong-fingerprint frames, Results from a stranger and a
// flood of Hellos from many identities are refused or dropped and counted in /metrics, while a real worker
// still runs the run to the same files as threads do. With CURVE keys, workers with an unknown key or no key get
// no connection at all (and say why), and the authorised one runs the run; a refused worker gets in once its key
// is authorised; a malformed file in authorized/, at start or later, is skipped (logged once, counted), not fatal.

#include <gtest/gtest.h>
#include <httplib.h>

#include <map>
#include <memory>
#include <regex>
#include <string>
#include <vector>
#include <zmq.hpp>

#include "common/program/build_fingerprint.h"
#include "common/text/text_format.h"
#include "coordinator_run_fixture.h"
#include "rogue_peer.h"
#include "wire.pb.h"

namespace {

using namespace poet::testing;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

// CoordinatorRunTest, and CURVE keys made by poetctl keygen.
class HostilePeersTest : public CoordinatorRunTest {
 protected:
  // Runs `poetctl keygen ARGS...` and expects it to succeed.
  void keygen(std::vector<std::string> args) {
    args.insert(args.begin(), "keygen");
    const int code = wait(spawn(POETCTL_BIN, std::move(args), "keygen"));
    ASSERT_EQ(code, 0) << read(root_ / "keygen.err");
  }

  // keys/: the coordinator's pair and an authorised worker's; intruder/: a valid worker pair, not authorised, with
  // the coordinator's public key.
  void make_keys() {
    keygen({(root_ / "keys").string(), "coordinator"});
    keygen({(root_ / "keys").string(), "worker", "--authorize"});
    keygen({(root_ / "intruder").string(), "worker"});
    fs::copy_file(root_ / "keys" / "coordinator.key", root_ / "intruder" / "coordinator.key");
  }
};

TEST_F(HostilePeersTest, RoguePeersAreCountedAndARealWorkerIsStillServed) {
  const fs::path reference = threads_run();
  const pid_t pid = coordinator(root_ / "H", {"--listen", "tcp://127.0.0.1:*"}, "H");
  const std::string endpoint = await_log("H", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  const std::string port = await_log("H", "status: http://127.0.0.1:([0-9]+)/status");
  ASSERT_FALSE(endpoint.empty());
  ASSERT_FALSE(port.empty());

  zmq::context_t context(1);
  zmq::socket_t rogue = rogue_socket(context, endpoint, "rogue");
  const std::string good_hello = hello(poet::wire::PROTOCOL_VERSION, poet::build_fingerprint_digest());
  rogue.send(zmq::str_buffer("\xff\x01 garbage that is no protobuf \x80\x80"));
  rogue.send(zmq::buffer(good_hello.substr(0, good_hello.size() / 2)));  // truncated
  rogue.send(zmq::str_buffer("part"), zmq::send_flags::sndmore);
  rogue.send(zmq::str_buffer("two"));                     // a message of two frames
  rogue.send(zmq::buffer(std::string(2 << 20, '\x0a')));  // 2 MB: over the coordinator's 1 MB cap
  poet::wire::WorkerMessage stranger_result;
  stranger_result.mutable_result()->set_job_id(12345);
  rogue.send(zmq::buffer(stranger_result.SerializeAsString()));
  const auto rejoin = answer(rogue);
  ASSERT_TRUE(rejoin && rejoin->has_rejoin()) << "a Result from a stranger is answered with Rejoin";
  rogue.send(zmq::buffer(hello(99, poet::build_fingerprint_digest())));
  const auto old_version = answer(rogue);
  ASSERT_TRUE(old_version && old_version->has_refused());
  // both versions named, as docs/compatibility.md promises
  EXPECT_TRUE(contains(old_version->refused().reason(),
                       "protocol version 99, the coordinator speaks " + std::to_string(poet::wire::PROTOCOL_VERSION)))
      << old_version->refused().reason();
  rogue.send(zmq::buffer(hello(poet::wire::PROTOCOL_VERSION, 0x1234)));
  const auto other_build = answer(rogue);
  ASSERT_TRUE(other_build && other_build->has_refused());
  EXPECT_TRUE(contains(other_build->refused().reason(),
                       "build fingerprint 0000000000001234 differs from the "
                       "coordinator's " +
                           poet::hex_text(poet::build_fingerprint_digest())))
      << other_build->refused().reason();
  {  // 20 MB: over ZMQ_MAXMSGSIZE, so libzmq drops this peer's connection before the coordinator sees it
    zmq::socket_t huge = rogue_socket(context, endpoint, "huge");
    huge.send(zmq::buffer(std::string(20 << 20, 'x')));
  }

  // a flood of Hellos from 300 identities that never say anything more: welcomed, never given work
  constexpr int kFlood = 300;
  std::vector<zmq::socket_t> flood;
  for (int i = 0; i < kFlood; ++i) {
    flood.push_back(rogue_socket(context, endpoint, "fake-" + std::to_string(i)));
    flood.back().send(zmq::buffer(good_hello));
  }

  std::map<std::string, double> m;
  for (int i = 0; i < 100; ++i) {  // published twice a second
    m = metrics(std::stoi(port));
    if (m["poet_workers_joined_total"] >= kFlood && m[dropped("oversized")] >= 1) break;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_GE(m[dropped("malformed")], 3) << "garbage, truncated, two frames";
  EXPECT_GE(m[dropped("oversized")], 1);
  EXPECT_EQ(m[dropped("wrong_version")], 1);
  EXPECT_EQ(m[dropped("wrong_fingerprint")], 1);
  EXPECT_GE(m[dropped("unknown_peer")], 1);
  EXPECT_GE(m["poet_workers_joined_total"], kFlood);
  EXPECT_EQ(m["poet_in_flight_jobs"], 0) << "a peer that only said Hello holds no work";

  // the real worker runs the run, while a second flood arrives
  const pid_t worker = spawn(POET_WORKER_BIN, {"--connect", endpoint, "--threads", "2"}, "worker");
  await_log("H", "(iteration [0-9]+):");
  for (int i = 0; i < kFlood; ++i) {
    flood.push_back(rogue_socket(context, endpoint, "late-" + std::to_string(i)));
    flood.back().send(zmq::buffer(good_hello));
  }
  EXPECT_EQ(wait(pid), 0) << read(root_ / "H.err");
  expect_same_run(reference, root_ / "H");
  EXPECT_EQ(wait(worker), 0);
  // the log says what was refused without a line per frame
  const std::string log = read(root_ / "H.err");
  EXPECT_TRUE(contains(log, "malformed")) << log;
  EXPECT_LT(std::count(log.begin(), log.end(), '\n'), 200) << "the log is flooded:\n" << log;
}

TEST_F(HostilePeersTest, WithCurveOnlyAWorkerWithAnAuthorisedKeyGetsWork) {
  const fs::path reference = threads_run();
  const fs::path keys = root_ / "keys";
  const fs::path intruder_keys = root_ / "intruder";
  make_keys();
  EXPECT_EQ(fs::status(keys / "coordinator.key_secret").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);

  const pid_t pid = coordinator(root_ / "C", {"--listen", "tcp://127.0.0.1:*", "--curve-keys", keys.string()}, "C");
  const std::string endpoint = await_log("C", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  const std::string port = await_log("C", "status: http://127.0.0.1:([0-9]+)/status");
  ASSERT_FALSE(endpoint.empty());
  ASSERT_FALSE(port.empty());
  const pid_t intruder =
      spawn(POET_WORKER_BIN, {"--connect", endpoint, "--curve-keys", intruder_keys.string()}, "intruder");
  const pid_t keyless = spawn(POET_WORKER_BIN, {"--connect", endpoint}, "keyless");
  await_log("intruder", "(refused this worker's CURVE key)");
  // the mismatch of mechanisms, or a reset that overtook the coordinator's greeting
  await_log("keyless", "(security handshake with|hung up during the handshake)");
  await_log("C", "(refused a worker with CURVE key)");
  await_log("C", "(waiting for workers)");
  EXPECT_GE(metrics(std::stoi(port))[dropped("unauthorised_key")], 1);

  const pid_t worker = spawn(POET_WORKER_BIN, {"--connect", endpoint, "--curve-keys", keys.string()}, "worker");
  EXPECT_EQ(wait(pid), 0) << read(root_ / "C.err");
  expect_same_run(reference, root_ / "C");
  EXPECT_EQ(wait(worker), 0);
  for (pid_t refused : {intruder, keyless}) {
    ASSERT_EQ(children_.ended(refused), std::nullopt) << "a refused worker keeps trying until stopped";
    ASSERT_EQ(::kill(refused, SIGTERM), 0);
    EXPECT_EQ(wait(refused), 0);
  }
  for (const char* name : {"intruder", "keyless"})
    EXPECT_FALSE(contains(read(root_ / (std::string(name) + ".err")), "welcomed")) << name << " got in";
}

TEST_F(HostilePeersTest, AKeyAuthorisedLaterLetsTheRefusedWorkerIn) {
  const fs::path reference = threads_run();
  const fs::path keys = root_ / "keys";
  keygen({keys.string(), "coordinator"});
  keygen({keys.string(), "worker"});  // not authorised yet
  fs::create_directories(keys / "authorized");
  const pid_t pid = coordinator(root_ / "C", {"--listen", "tcp://127.0.0.1:*", "--curve-keys", keys.string()}, "C");
  const std::string endpoint = await_log("C", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(endpoint.empty());
  const pid_t worker = spawn(POET_WORKER_BIN, {"--connect", endpoint, "--curve-keys", keys.string()}, "worker");
  await_log("worker", "(refused this worker's CURVE key)");

  // copied in while both run (as an operator would, then renamed: a half-written file is not a key yet)
  fs::copy_file(keys / "worker.key", keys / "authorized" / "worker.key.partial");
  fs::rename(keys / "authorized" / "worker.key.partial", keys / "authorized" / "worker.key");
  // (the coordinator's log too: once, under load, every reconnection after the first refusal went unanswered)
  ASSERT_EQ(await_log("worker", "(welcomed) by the coordinator"), "welcomed")
      << read(root_ / "worker.err") << "\ncoordinator:\n"
      << read(root_ / "C.err");
  EXPECT_EQ(wait(pid), 0) << read(root_ / "C.err");
  expect_same_run(reference, root_ / "C");
  EXPECT_EQ(wait(worker), 0);
}

TEST_F(HostilePeersTest, AMalformedKeyFileIsSkippedLoggedOnceAndCounted) {
  const fs::path reference = threads_run();
  const fs::path keys = root_ / "keys";
  const fs::path intruder_keys = root_ / "intruder";
  make_keys();
  // a file that holds no key is there from the start: skipped as one that appears later is
  std::ofstream(keys / "authorized" / "junk.key") << "not a key\n";
  const pid_t pid = coordinator(root_ / "C", {"--listen", "tcp://127.0.0.1:*", "--curve-keys", keys.string()}, "C");
  const std::string endpoint = await_log("C", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  const std::string port = await_log("C", "status: http://127.0.0.1:([0-9]+)/status");
  ASSERT_FALSE(endpoint.empty());
  ASSERT_FALSE(port.empty());
  EXPECT_TRUE(contains(read(root_ / "C.err"), "skipped " + (keys / "authorized" / "junk.key").string()))
      << read(root_ / "C.err");
  EXPECT_EQ(metrics(std::stoi(port))["poet_skipped_key_files_total"], 1);

  // half a key copied in beside the good one, then handshakes: the intruder's, again and again, and the worker's
  const std::string good = read(keys / "authorized" / "worker.key");
  std::ofstream(keys / "authorized" / "half.key") << good.substr(0, 20);
  const pid_t intruder =
      spawn(POET_WORKER_BIN, {"--connect", endpoint, "--curve-keys", intruder_keys.string()}, "intruder");
  await_log("intruder", "(refused this worker's CURVE key)");
  await_log("C", "(half.key)");
  EXPECT_EQ(metrics(std::stoi(port))["poet_skipped_key_files_total"], 2);

  const pid_t worker = spawn(POET_WORKER_BIN, {"--connect", endpoint, "--curve-keys", keys.string()}, "worker");
  ASSERT_EQ(await_log("worker", "(welcomed) by the coordinator"), "welcomed") << read(root_ / "worker.err");
  EXPECT_EQ(wait(pid), 0) << read(root_ / "C.err");
  expect_same_run(reference, root_ / "C");
  EXPECT_EQ(wait(worker), 0);
  const std::string log = read(root_ / "C.err");
  for (const std::string file : {"half.key", "junk.key"}) {
    size_t lines = 0;
    for (size_t at = log.find(file); at != std::string::npos; at = log.find(file, at + 1)) ++lines;
    EXPECT_EQ(lines, 1u) << file << " logged more than once: " << log;
  }
  ASSERT_EQ(::kill(intruder, SIGTERM), 0);
  EXPECT_EQ(wait(intruder), 0);
}

// A worker refused for wrong results under CURVE stays refused by its key: the same key on a new socket, from a new
// process, is refused at the handshake, in this run and after a resume (the key is kept in the run directory).
TEST_F(HostilePeersTest, AWorkerRefusedForWrongResultsStaysRefusedByItsKey) {
  const fs::path keys = root_ / "keys";
  const fs::path liar_keys = root_ / "intruder";
  make_keys();
  fs::copy_file(liar_keys / "worker.key", keys / "authorized" / "liar.key");
  std::string liar_key = read(liar_keys / "worker.key");
  liar_key.erase(liar_key.find_last_not_of("\n") + 1);
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 100000");  // still going
  const fs::path dir = root_ / "C";
  const std::vector<std::string> listen = {"--listen",    "tcp://127.0.0.1:*", "--curve-keys",
                                           keys.string(), "--verify-fraction", "1"};
  const pid_t pid = coordinator(dir, listen, "C");
  const std::string endpoint = await_log("C", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(endpoint.empty());
  const pid_t honest =
      spawn(POET_WORKER_BIN, {"--connect", endpoint, "--curve-keys", keys.string(), "--threads", "1"}, "honest");
  await_log("honest", "(welcomed) by the coordinator");
  const pid_t liar = spawn(POET_TEST_WORKER_BIN,
                           {"--connect", endpoint, "--curve-keys", liar_keys.string(), "--threads", "1", "--fault",
                            "wrong-results", "--name", "the-liar"},
                           "liar");
  EXPECT_EQ(wait(liar), 2) << "refused for wrong results: " << read(root_ / "liar.err");
  EXPECT_TRUE(contains(read(dir / "refused_keys.txt"), liar_key)) << read(dir / "refused_keys.txt");

  // the same key again, an honest process this time: refused at the handshake
  const auto again = [&](const std::string& at, const std::string& name) {
    const pid_t worker =
        spawn(POET_WORKER_BIN, {"--connect", at, "--curve-keys", liar_keys.string(), "--threads", "1"}, name);
    await_log(name, "(refused this worker's CURVE key)");
    ASSERT_EQ(::kill(worker, SIGTERM), 0);
    EXPECT_EQ(wait(worker), 0);
    EXPECT_FALSE(contains(read(root_ / (name + ".err")), "welcomed")) << name << " got in";
  };
  again(endpoint, "again");
  EXPECT_TRUE(contains(read(root_ / "C.err"), "a worker holding it returned wrong results")) << read(root_ / "C.err");

  // and after a resume
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  EXPECT_EQ(wait(pid), 130);
  std::vector<std::string> resume = {"--run-dir",        dir.string(),  "--resume",      "--quiet",
                                     "--status-address", "127.0.0.1:0", "--liveness-ms", "1000"};
  resume.insert(resume.end(), listen.begin(), listen.end());
  const pid_t resumed = spawn(POET_COORDINATOR_BIN, resume, "R");
  const std::string endpoint_after = await_log("R", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(endpoint_after.empty());
  EXPECT_TRUE(contains(read(root_ / "R.err"), "1 worker key(s) refused for wrong results earlier"))
      << read(root_ / "R.err");
  again(endpoint_after, "after-resume");
  ASSERT_EQ(::kill(resumed, SIGINT), 0);
  EXPECT_EQ(wait(resumed), 130);
  ASSERT_EQ(::kill(honest, SIGTERM), 0);
  EXPECT_EQ(wait(honest), 0);
}

// Two processes holding one CURVE key, one honest and one that lies: when the liar is found wrong, the honest
// twin's connection is refused at once, in the same turn of the coordinator (not when one of its own answers is
// drawn for a check, which for an honest one is never), and every handshake with the key after is refused. The run
// ends as the undisturbed one.
TEST_F(HostilePeersTest, ARefusedKeyEndsEveryConnectionThatHoldsItAtOnce) {
  const fs::path reference = threads_run();
  const fs::path keys = root_ / "keys";
  const fs::path shared_keys = root_ / "intruder";  // the twins' key, authorised below
  make_keys();
  fs::copy_file(shared_keys / "worker.key", keys / "authorized" / "twins.key");
  const fs::path dir = root_ / "C";
  const pid_t pid =
      coordinator(dir, {"--listen", "tcp://127.0.0.1:*", "--curve-keys", keys.string(), "--verify-fraction", "1"}, "C");
  const std::string endpoint = await_log("C", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(endpoint.empty());
  const auto worker = [&](const fs::path& key_dir, const std::string& name, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"--connect", endpoint, "--curve-keys", key_dir.string(),
                                     "--threads", "1",      "--name",       name};
    args.insert(args.end(), extra.begin(), extra.end());
    return spawn(extra.empty() ? POET_WORKER_BIN : POET_TEST_WORKER_BIN, args, name);  // a fault: the test worker
  };
  const pid_t honest = worker(keys, "honest");
  await_log("honest", "(welcomed) by the coordinator");
  const pid_t twin = worker(shared_keys, "twin");
  await_log("twin", "(welcomed) by the coordinator");
  const pid_t liar = worker(shared_keys, "the-liar", {"--fault", "wrong-results"});

  EXPECT_EQ(wait(liar), 2) << "refused for wrong results: " << read(root_ / "the-liar.err");
  EXPECT_EQ(wait(twin), 2) << "refused for its key: " << read(root_ / "twin.err");
  EXPECT_TRUE(contains(read(root_ / "twin.err"),
                       "refused by the coordinator: this worker holds the CURVE key of a worker refused for wrong "
                       "results"))
      << read(root_ / "twin.err");
  // the two refusals are consecutive lines of the coordinator's log: one turn of its socket thread
  const std::string log = read(root_ / "C.err");
  const std::regex both(R"(worker the-liar returned results that[^\n]*\n[^\n]*worker twin holds the CURVE key of a )"
                        R"(worker refused for wrong results: refused)");
  EXPECT_TRUE(std::regex_search(log, both)) << log;

  // a third process with the key is refused at the handshake
  const pid_t again = worker(shared_keys, "again");
  await_log("again", "(refused this worker's CURVE key)");
  ASSERT_EQ(::kill(again, SIGTERM), 0);
  EXPECT_EQ(wait(again), 0);
  EXPECT_FALSE(contains(read(root_ / "again.err"), "welcomed")) << "the key got in again";

  EXPECT_EQ(wait(pid), 0) << read(root_ / "C.err");
  expect_same_run(reference, dir);
  EXPECT_EQ(wait(honest), 0);
}

TEST_F(HostilePeersTest, CurveKeyProblemsAreRefusedAtStart) {
  const fs::path keys = root_ / "keys";
  fs::create_directories(keys);
  const pid_t no_keys = coordinator(root_ / "X", {"--local-workers", "1", "--curve-keys", keys.string()}, "nokeys");
  EXPECT_EQ(wait(no_keys), 2);
  EXPECT_TRUE(contains(read(root_ / "nokeys.err"), "coordinator.key")) << read(root_ / "nokeys.err");
  keygen({keys.string(), "coordinator"});
  keygen({keys.string(), "worker"});  // not authorised, yet local workers would use it
  fs::create_directories(keys / "authorized");
  const pid_t unauthorised =
      coordinator(root_ / "Y", {"--local-workers", "1", "--curve-keys", keys.string()}, "unauth");
  EXPECT_EQ(wait(unauthorised), 2);
  EXPECT_TRUE(contains(read(root_ / "unauth.err"), "not in authorized")) << read(root_ / "unauth.err");
  const pid_t worker = spawn(POET_WORKER_BIN, {"--connect", "tcp://127.0.0.1:1", "--curve-keys", root_.string()}, "w");
  EXPECT_EQ(wait(worker), 2);
  EXPECT_TRUE(contains(read(root_ / "w.err"), "worker.key")) << read(root_ / "w.err");
}

}  // namespace
