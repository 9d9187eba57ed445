// What an operator's slip or a crash must not do to a run directory, with the coordinator as a real process: a
// SIGKILLed coordinator leaves no worker behind; a directory holding a run's files without its checkpoint is
// not overwritten; the owner's lock holds when run.lock is deleted; changed logs are refused on resume; a missing
// or damaged config.textproto is written again; a port in use, a directory that cannot be written and a forged
// checkpoint are found before any work, naming what is wrong.

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "coordinator_run_fixture.h"
#include "loopback_port.h"
#include "run_directory/files/checkpoint_file.h"

namespace {

using namespace poet::testing;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

// A process that exists and is not a zombie (an orphan's zombie waits for a reaper that may never come here).
bool running(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return false;
  const size_t close = line.rfind(')');
  return close != std::string::npos && close + 2 < line.size() && line[close + 2] != 'Z';
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

class RunDirectoryTrustTest : public CoordinatorRunTest {
 protected:
  // `poet-coordinator --run-dir DIR --resume` with extra arguments, without a status socket.
  pid_t resume(const fs::path& dir, std::vector<std::string> extra, const std::string& name) {
    std::vector<std::string> args = {"--run-dir", dir.string(), "--resume", "--quiet", "--status-address", ""};
    args.insert(args.end(), extra.begin(), extra.end());
    return spawn(POET_COORDINATOR_BIN, args, name);
  }

  // Runs a command (argv[0] a program in /usr/bin or /bin) for at most a minute; its exit code, its output in
  // command.out and command.err.
  int run_command(std::vector<std::string> args) {
    args[0] = fs::exists("/usr/bin/" + args[0]) ? "/usr/bin/" + args[0] : "/bin/" + args[0];
    return children_.run(std::move(args), root_ / "command", 60s).code;
  }
};

TEST_F(RunDirectoryTrustTest, LocalWorkersEndWithTheirCoordinatorEvenWhenItIsKilled) {
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 999");
  const pid_t pid = coordinator(root_ / "K", {"--local-workers", "2"}, "K");
  await_log("K", "(iteration [0-9]+):");
  std::vector<pid_t> workers = children_of(pid);
  ASSERT_EQ(workers.size(), 2u);
  for (pid_t w : workers) ASSERT_TRUE(running(w));
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  EXPECT_EQ(wait(pid), 128 + SIGKILL);
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < deadline && (running(workers[0]) || running(workers[1])))
    std::this_thread::sleep_for(20ms);
  for (pid_t w : workers) {
    EXPECT_FALSE(running(w)) << "worker " << w << " outlived its coordinator";
    ::kill(w, SIGKILL);  // whatever happened, nothing is left behind
  }
}

TEST_F(RunDirectoryTrustTest, ARunsFilesWithoutTheirCheckpointAreNotOverwritten) {
  const fs::path dir = threads_run();
  fs::remove(dir / "checkpoint.pb");
  const std::string events = read(dir / "events.jsonl");
  const std::string stats = read(dir / "pair_stats.csv");
  const pid_t again = coordinator(dir, {"--threads", "2"}, "again");  // the original command, without --resume
  EXPECT_EQ(wait(again), 2);
  const std::string err = read(root_ / "again.err");
  EXPECT_TRUE(contains(err, "holds files of an earlier run but no checkpoint.pb")) << err;
  EXPECT_TRUE(contains(err, "events.jsonl (")) << err;
  EXPECT_TRUE(contains(err, "move them away")) << err;
  EXPECT_EQ(read(dir / "events.jsonl"), events);
  EXPECT_EQ(read(dir / "pair_stats.csv"), stats);
}

TEST_F(RunDirectoryTrustTest, TheLockHoldsWhenRunLockIsDeleted) {
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 999");
  const pid_t owner = coordinator(root_ / "L", {"--threads", "1"}, "owner");
  await_log("owner", "(iteration [0-9]+):");
  ASSERT_TRUE(fs::remove(root_ / "L" / "run.lock"));
  const pid_t second = resume(root_ / "L", {}, "second");
  EXPECT_EQ(wait(second), 2);
  const std::string err = read(root_ / "second.err");
  EXPECT_TRUE(contains(err, "is in use by another process")) << err;
  ASSERT_EQ(::kill(owner, SIGKILL), 0);
  EXPECT_EQ(wait(owner), 128 + SIGKILL);
}

TEST_F(RunDirectoryTrustTest, LogsChangedAfterTheCheckpointAreRefusedAndReportedByTheReport) {
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 3");
  const pid_t first = coordinator(root_ / "D", {"--threads", "2"}, "first");
  ASSERT_EQ(wait(first), 0) << read(root_ / "first.err");
  const fs::path stats = root_ / "D" / "pair_stats.csv";
  const std::string original = read(stats);
  std::string damaged = original;
  const size_t digit = damaged.find_first_of("123456789", damaged.find('\n') + 1);
  ASSERT_NE(digit, std::string::npos);
  damaged[digit] = damaged[digit] == '9' ? '8' : static_cast<char>(damaged[digit] + 1);
  write_text(stats, damaged);

  const pid_t resumed = resume(root_ / "D", {"--iterations", "6"}, "resumed");
  EXPECT_EQ(wait(resumed), 2);
  const std::string err = read(root_ / "resumed.err");
  EXPECT_TRUE(contains(err, "pair_stats.csv")) << err;
  EXPECT_TRUE(contains(err, "CRC-32 mismatch")) << err;
  EXPECT_EQ(read(stats), damaged) << "nothing changed";

  const pid_t report = spawn(POET_REPORT_BIN, {"--run-dir", (root_ / "D").string()}, "report");
  EXPECT_NE(wait(report), 0);
  EXPECT_TRUE(contains(read(root_ / "report.err"), "CRC-32 mismatch")) << read(root_ / "report.err");
}

TEST_F(RunDirectoryTrustTest, AMissingOrDamagedConfigIsWrittenAgainOnResume) {
  const fs::path reference = threads_run();
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 2");
  const pid_t first = coordinator(root_ / "C", {"--threads", "2"}, "first");
  ASSERT_EQ(wait(first), 0) << read(root_ / "first.err");
  const std::string config = read(root_ / "C" / "config.textproto");
  fs::remove(root_ / "C" / "config.textproto");
  const pid_t second = resume(root_ / "C", {"--iterations", "4"}, "second");
  ASSERT_EQ(wait(second), 0) << read(root_ / "second.err");
  EXPECT_TRUE(contains(read(root_ / "second.err"), "config.textproto was missing: written again from the checkpoint"))
      << read(root_ / "second.err");

  write_text(root_ / "C" / "config.textproto", "mode: POET\nseed: 99\n");
  const pid_t third = resume(root_ / "C", {"--iterations", "6"}, "third");
  ASSERT_EQ(wait(third), 0) << read(root_ / "third.err");
  EXPECT_TRUE(contains(read(root_ / "third.err"), "differed from the run's config")) << read(root_ / "third.err");
  EXPECT_EQ(read(root_ / "C" / "config.textproto"), read(reference / "config.textproto"));
  expect_same_run(reference, root_ / "C");
}

TEST_F(RunDirectoryTrustTest, APortInUseIsFoundBeforeAnyFileIsWritten) {
  std::optional<LoopbackPort> taken(std::in_place, true);
  ASSERT_GT(taken->port(), 0);
  const std::string endpoint = taken->endpoint();
  const pid_t pid = coordinator(root_ / "P", {"--listen", endpoint}, "P");
  EXPECT_EQ(wait(pid), 2);
  taken.reset();
  EXPECT_TRUE(contains(read(root_ / "P.err"), "cannot listen on " + endpoint)) << read(root_ / "P.err");
  EXPECT_FALSE(fs::exists(root_ / "P" / "checkpoint.pb"));
  EXPECT_FALSE(fs::exists(root_ / "P" / "config.textproto"));
}

TEST_F(RunDirectoryTrustTest, ADirectoryThatCannotBeWrittenIsFoundBeforeAnIteration) {
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 2");
  const pid_t first = coordinator(root_ / "W", {"--threads", "2"}, "first");
  ASSERT_EQ(wait(first), 0) << read(root_ / "first.err");
  // the tests run as root, whom permissions do not stop: the immutable attribute does
  if (run_command({"chattr", "+i", (root_ / "W" / "policies").string()}) != 0)
    GTEST_SKIP() << "chattr +i is not available here: " << read(root_ / "command.err");
  const pid_t second = resume(root_ / "W", {"--iterations", "4"}, "second");
  const int code = wait(second);
  run_command({"chattr", "-i", (root_ / "W" / "policies").string()});
  EXPECT_EQ(code, 2);
  const std::string err = read(root_ / "second.err");
  EXPECT_TRUE(contains(err, "policies: cannot write files in it")) << err;
  EXPECT_FALSE(contains(err, "iteration 2")) << "no iteration ran: " << err;
}

TEST_F(RunDirectoryTrustTest, AForgedCheckpointWithInvalidUtf8IsRefusedNamingTheFile) {
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 2");
  const pid_t first = coordinator(root_ / "U", {"--threads", "2"}, "first");
  ASSERT_EQ(wait(first), 0) << read(root_ / "first.err");
  const fs::path path = root_ / "U" / "checkpoint.pb";
  poet::Expected<poet::pb::Checkpoint> checkpoint = poet::read_checkpoint_file(path);
  ASSERT_TRUE(checkpoint) << checkpoint.error();
  ASSERT_GT(checkpoint->pairs_size(), 0);
  checkpoint->mutable_pairs(0)->mutable_env()->mutable_encoding()->set_name("bad \xff\xfe name");
  write_text(path, poet::encode_checkpoint_file(*checkpoint));  // a valid CRC over the forged body
  const pid_t second = resume(root_ / "U", {"--iterations", "4"}, "second");
  EXPECT_EQ(wait(second), 2);
  const std::string err = read(root_ / "second.err");
  EXPECT_TRUE(contains(err, path.string())) << err;
  EXPECT_TRUE(contains(err, "UTF-8")) << err;
}

}  // namespace
