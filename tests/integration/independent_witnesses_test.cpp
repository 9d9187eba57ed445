// One party that lies cannot out-vote honest workers (coordinator/trust/verification.h, independent witnesses), with
// real processes on loopback: a liar that takes a new identity every two jobs, as anyone may without CURVE, and a
// liar holding one authorised CURVE key on four connections against two honest workers that share another key. Each
// run ends in the files of the run on threads, no honest worker is refused, and the liar is.

#include <gtest/gtest.h>
#include <signal.h>

#include <optional>
#include <string>
#include <vector>

#include "coordinator_run_fixture.h"

namespace {

using namespace poet::testing;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

int count_of(const std::string& text, const std::string& part) {
  int n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

class IndependentWitnessesTest : public CoordinatorRunTest {
 protected:
  pid_t liar(const std::string& endpoint, const std::string& name, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"--connect", endpoint,        "--threads", "1",
                                     "--fault",   "wrong-results", "--name",    name};
    args.insert(args.end(), extra.begin(), extra.end());
    return spawn(POET_TEST_WORKER_BIN, args, name);
  }
  std::vector<pid_t> honest_workers(const std::string& endpoint, std::vector<std::string> extra = {}) {
    std::vector<pid_t> pids;
    for (const std::string name : {"honest-a", "honest-b"}) {
      std::vector<std::string> args = {"--connect", endpoint, "--threads", "1", "--name", name};
      args.insert(args.end(), extra.begin(), extra.end());
      pids.push_back(spawn(POET_WORKER_BIN, args, name));
      await_log(name, "(welcomed) by the coordinator");
    }
    return pids;
  }
  void keygen(std::vector<std::string> args) {
    args.insert(args.begin(), "keygen");
    ASSERT_EQ(wait(spawn(POETCTL_BIN, std::move(args), "keygen")), 0) << read(root_ / "keygen.err");
  }
  // The run ended as on threads, the honest workers were never refused, and the liar was.
  void expect_honest_run(const fs::path& reference, const std::string& name, pid_t coordinator_pid,
                         const std::vector<pid_t>& honest) {
    EXPECT_EQ(wait(coordinator_pid), 0) << read(root_ / (name + ".err"));
    expect_same_run(reference, root_ / name);
    const std::string log = read(root_ / (name + ".err"));
    EXPECT_FALSE(contains(log, "[error] worker honest-")) << "an honest worker was refused:\n" << log;
    EXPECT_TRUE(contains(log, "[error] worker liar-")) << "the liar was not refused:\n" << log;
    for (const pid_t h : honest) EXPECT_EQ(wait(h), 0);
  }
};

TEST_F(IndependentWitnessesTest, ALiarWithANewIdentityEveryTwoJobsChangesNothing) {
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 16");  // time for identities
  const fs::path reference = threads_run();
  // no CURVE: verification at its default for an open port
  const pid_t pid = coordinator(root_ / "S", {"--listen", "tcp://127.0.0.1:*"}, "S");
  const std::string endpoint = await_log("S", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(endpoint.empty());
  const std::vector<pid_t> honest = honest_workers(endpoint);
  const auto run_over = [&] { return contains(read(root_ / "S.err"), "run finished at iteration"); };
  int identities = 0;
  for (; identities < 12 && !run_over(); ++identities) {
    const std::string name = "liar-" + std::to_string(identities);
    const pid_t identity = liar(endpoint, name);
    // two wrong answers, then gone (its answers held), and a new connection under another name
    const auto deadline = std::chrono::steady_clock::now() + 20s;
    std::optional<int> ended;
    while (std::chrono::steady_clock::now() < deadline && !run_over() && !ended &&
           count_of(read(root_ / (name + ".err")), "a wrong answer to job") < 2) {
      ended = children_.ended(identity);
      std::this_thread::sleep_for(10ms);
    }
    if (!ended) {
      ::kill(identity, SIGTERM);
      wait(identity);
    }
  }
  EXPECT_GE(identities, 3);
  expect_honest_run(reference, "S", pid, honest);
}

TEST_F(IndependentWitnessesTest, ALiarOnFourConnectionsOfOneKeyIsRefusedAndHonestWorkersSharingAKeyAreNot) {
  const fs::path reference = threads_run();
  const fs::path keys = root_ / "keys", liar_keys = root_ / "liar-keys";
  keygen({keys.string(), "coordinator"});
  keygen({keys.string(), "worker", "--authorize"});  // the honest workers' one key, as Compose has it
  keygen({liar_keys.string(), "worker"});
  fs::copy_file(keys / "coordinator.key", liar_keys / "coordinator.key");
  fs::copy_file(liar_keys / "worker.key", keys / "authorized" / "liar.key");  // authorised: an insider
  const pid_t pid = coordinator(
      root_ / "K", {"--listen", "tcp://127.0.0.1:*", "--curve-keys", keys.string(), "--verify-fraction", "0.05"}, "K");
  const std::string endpoint = await_log("K", "workers connect to (tcp://[0-9.]+:[0-9]+)");
  ASSERT_FALSE(endpoint.empty());
  const std::vector<pid_t> honest = honest_workers(endpoint, {"--curve-keys", keys.string()});
  std::vector<pid_t> liars;
  for (int i = 0; i < 4; ++i)
    liars.push_back(liar(endpoint, "liar-" + std::to_string(i), {"--curve-keys", liar_keys.string()}));
  expect_honest_run(reference, "K", pid, honest);
  const std::string refused = read(root_ / "K" / "refused_keys.txt");
  EXPECT_TRUE(contains(refused, read(liar_keys / "worker.key").substr(0, 40))) << refused;
  EXPECT_FALSE(contains(refused, read(keys / "worker.key").substr(0, 40))) << refused;
  for (const pid_t l : liars) {
    const int code = wait(l);
    EXPECT_TRUE(code == 2 || code == 0) << code;  // refused; or, joined once the run was over, told it is finished
  }
}

}  // namespace
