// Tests run_directory/files/run_directory.cpp: the files a run writes and their contents, refusing to start over an
// existing run or to share a directory with another owner, resume cutting the logs back to the last checkpoint
// and bringing the pair files up to it, pair files that never run ahead of the checkpoint, and damaged
// checkpoints giving errors.

#include "run_directory/files/run_directory.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/formats/envgen/env_json.h"
#include "common/formats/policy/policy_file.h"
#include "common/program/command_line.h"
#include "run_directory/config/run_config.h"
#include "run_directory/files/annecs_log.h"
#include "run_directory/files/checkpoint.h"
#include "run_directory/files/crc32.h"
#include "run_directory/files/event_json.h"
#include "scratch_dir.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {
namespace {

namespace fs = std::filesystem;

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

pb::RunConfig small_config() {
  pb::RunConfig config;
  config.set_seed(7);
  config.set_iterations(6);
  config.mutable_es()->set_perturbations(4);
  config.mutable_poet()->set_mutation_interval(1);
  return config;
}

Pair make_pair(int id) {
  Pair p;
  p.id = id;
  p.env.seed = static_cast<uint32_t>(100 + id);
  RandomStream rng(stream_key(static_cast<uint64_t>(id), "run_directory_test"));
  p.theta = random_params(rng);
  p.best_theta = random_params(rng);
  p.optimizer.m.assign(kParamCount, 0.0);
  p.optimizer.v.assign(kParamCount, 0.0);
  p.optimizer.lr = 0.01;
  p.optimizer.sigma = 0.1;
  p.latest_score = -50.25 + id;
  p.best_score = 1.0 / 3;
  p.best_iteration = 0;
  return p;
}

// The first pair and a child admitted at iteration 1: a state the engine could have written.
RunState two_pair_state() {
  RunState state;
  state.settings = run_settings(small_config());
  state.pairs = {make_pair(0), make_pair(1)};
  state.pairs[1].parent_id = 0;
  state.pairs[1].created_iteration = 1;
  state.pairs[1].best_iteration = 1;
  state.next_pair_id = 2;
  state.next_iteration = 1;
  state.counters.children_tried = state.counters.children_passed_mc = state.counters.children_admitted = 1;
  return state;
}

pb::Checkpoint read_checkpoint(const fs::path& path) {
  Expected<pb::Checkpoint> checkpoint = read_checkpoint_file(path);
  EXPECT_TRUE(checkpoint) << checkpoint.error();
  return checkpoint ? *checkpoint : pb::Checkpoint();
}

// A report for iteration t with one event and one stats row per pair of the state.
IterationReport report_for(const RunState& state, int t) {
  IterationReport report;
  report.iteration = t;
  report.events.push_back(SolvedEvent{0, "flat", 0.1 * t, t});
  for (const Pair& pair : state.pairs) {
    PairStatsRow row;
    row.iteration = t;
    row.pair = pair.id;
    row.env = "flat,with comma";
    row.score = 1.0 / 3 + t;
    row.lr = 0.009999000000000001;
    report.stats.push_back(row);
  }
  return report;
}

std::string events_text(const IterationReport& report) {
  std::string text;
  for (const auto& e : events_json(report)) text += e.dump() + "\n";
  return text;
}

std::string stats_text(const IterationReport& report) {
  std::string text;
  for (const PairStatsRow& row : report.stats) text += pair_stats_row(row);
  return text;
}

// A fresh directory per test, removed afterwards even when the test fails.
class RunDirectoryTest : public ::testing::Test {
 protected:
  // Creates the run and saves state; fails the test on any error.
  RunDirectory create_and_save(const RunState& state) {
    Expected<RunDirectory> dir = RunDirectory::create(dir_, small_config());
    EXPECT_TRUE(dir) << dir.error();
    if (!dir) throw std::runtime_error(dir.error());
    const auto error = dir->save(state);
    EXPECT_FALSE(error) << *error;
    return std::move(*dir);
  }

  poet::testing::ScratchDir scratch_;
  fs::path root_ = scratch_.path();
  fs::path dir_ = root_ / "run";
};

TEST_F(RunDirectoryTest, CreateAndSaveWriteTheFiles) {
  const RunState state = two_pair_state();
  Expected<RunDirectory> dir = RunDirectory::create(dir_, small_config());
  ASSERT_TRUE(dir) << dir.error();
  EXPECT_EQ(dir->path(), dir_);
  EXPECT_FALSE(fs::exists(dir_ / kCheckpointFile));
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header());
  EXPECT_EQ(read(dir_ / kEventsFile), "");
  EXPECT_EQ(read(dir_ / kAnnecsFile), annecs_header());
  const Expected<pb::RunConfig> config = parse_run_config(read(dir_ / kConfigFile));
  ASSERT_TRUE(config) << config.error();
  EXPECT_EQ(config->SerializeAsString(), small_config().SerializeAsString());

  ASSERT_FALSE(dir->save(state));
  pb::Checkpoint checkpoint = read_checkpoint(dir_ / kCheckpointFile);
  EXPECT_EQ(checkpoint.events_bytes(), 0);
  EXPECT_EQ(checkpoint.stats_bytes(), static_cast<int64_t>(pair_stats_header().size()));
  EXPECT_EQ(checkpoint.events_crc32(), 0u);
  EXPECT_EQ(checkpoint.stats_crc32(), crc32_extend(0, pair_stats_header()));
  checkpoint.clear_events_bytes();
  checkpoint.clear_stats_bytes();
  checkpoint.clear_events_crc32();
  checkpoint.clear_stats_crc32();
  EXPECT_EQ(checkpoint.written_by(), project_version());
  checkpoint.clear_written_by();
  EXPECT_EQ(checkpoint.SerializeAsString(), to_checkpoint(small_config(), state).SerializeAsString());
  for (const Pair& pair : state.pairs) {
    const std::string stem = "pair-" + std::to_string(pair.id);
    EXPECT_EQ(read(dir_ / kEnvsDir / (stem + ".env.json")), env_def_json_text(pair.env));
    EXPECT_EQ(read(dir_ / kPoliciesDir / (stem + ".json")), policy_json_text(pair.theta, pair.latest_score));
    EXPECT_EQ(read(dir_ / kPoliciesDir / (stem + ".best.json")), policy_json_text(pair.best_theta, pair.best_score));
  }
  for (const auto& entry : fs::recursive_directory_iterator(dir_))
    EXPECT_FALSE(contains(entry.path().filename().string(), ".tmp")) << entry.path();
}

TEST_F(RunDirectoryTest, RefusesToCreateOverAnExistingRun) {
  const RunState state = two_pair_state();
  { RunDirectory dir = create_and_save(state); }
  const std::string checkpoint = read(dir_ / kCheckpointFile);
  const Expected<RunDirectory> again = RunDirectory::create(dir_, small_config());
  ASSERT_FALSE(again);
  EXPECT_TRUE(contains(again.error(), "already holds a run; resume it or choose another directory")) << again.error();
  EXPECT_EQ(read(dir_ / kCheckpointFile), checkpoint);
}

TEST_F(RunDirectoryTest, CreateMayStartOverWhereAStartEndedBeforeItsFirstCheckpoint) {
  { ASSERT_TRUE(RunDirectory::create(dir_, small_config())); }  // config and the stats header, nothing more
  const Expected<RunDirectory> again = RunDirectory::create(dir_, small_config());
  ASSERT_TRUE(again) << again.error();
  EXPECT_EQ(read(dir_ / kEventsFile), "");
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header());
}

TEST_F(RunDirectoryTest, CreateRefusesAnEarlierRunsFilesWithoutTheirCheckpoint) {
  const RunState state = two_pair_state();
  {
    RunDirectory dir = create_and_save(state);
    dir.append(report_for(state, 0));
    ASSERT_FALSE(dir.save(state));
  }
  fs::remove(dir_ / kCheckpointFile);
  const std::string events = read(dir_ / kEventsFile);
  const std::string stats = read(dir_ / kStatsFile);
  const Expected<RunDirectory> again = RunDirectory::create(dir_, small_config());
  ASSERT_FALSE(again);
  for (const char* what : {"holds files of an earlier run but no checkpoint.pb", "events.jsonl (", "pair_stats.csv (",
                           "annecs.csv (", "envs/ (2 files)", "move them away"})
    EXPECT_TRUE(contains(again.error(), what)) << again.error();
  EXPECT_EQ(read(dir_ / kEventsFile), events);
  EXPECT_EQ(read(dir_ / kStatsFile), stats);
}

TEST_F(RunDirectoryTest, ResumeRefusesLogsChangedAfterTheCheckpoint) {
  RunState state = two_pair_state();
  {
    RunDirectory dir = create_and_save(state);
    dir.append(report_for(state, 0));
    state.next_iteration = 1;
    ASSERT_FALSE(dir.save(state));
  }
  for (const char* file : {kEventsFile, kStatsFile}) {
    const std::string original = read(dir_ / file);
    std::string damaged = original;
    const size_t digit = damaged.find_first_of("0123456789", damaged.size() / 2);
    ASSERT_NE(digit, std::string::npos);
    damaged[digit] = damaged[digit] == '9' ? '8' : static_cast<char>(damaged[digit] + 1);  // same length
    write(dir_ / file, damaged);
    const auto resumed = RunDirectory::resume(dir_);
    ASSERT_FALSE(resumed) << file;
    EXPECT_TRUE(contains(resumed.error(), file)) << resumed.error();
    EXPECT_TRUE(contains(resumed.error(), "CRC-32 mismatch")) << resumed.error();
    write(dir_ / file, original);
  }
  EXPECT_TRUE(RunDirectory::resume(dir_));
}

TEST_F(RunDirectoryTest, ResumeWritesAMissingOrChangedConfigAgain) {
  const RunState state = two_pair_state();
  { RunDirectory dir = create_and_save(state); }
  const std::string config = read(dir_ / kConfigFile);
  fs::remove(dir_ / kConfigFile);
  {
    const auto resumed = RunDirectory::resume(dir_);
    ASSERT_TRUE(resumed) << resumed.error();
    ASSERT_EQ(resumed->first.repairs().size(), 1u);
    EXPECT_TRUE(contains(resumed->first.repairs()[0], "was missing")) << resumed->first.repairs()[0];
  }
  EXPECT_EQ(read(dir_ / kConfigFile), config);
  write(dir_ / kConfigFile, "seed: 99\n\x01 not even text");
  {
    const auto resumed = RunDirectory::resume(dir_);
    ASSERT_TRUE(resumed) << resumed.error();
    ASSERT_EQ(resumed->first.repairs().size(), 1u);
    EXPECT_TRUE(contains(resumed->first.repairs()[0], "differed from the run's config")) << resumed->first.repairs()[0];
  }
  EXPECT_EQ(read(dir_ / kConfigFile), config);
  const auto untouched = RunDirectory::resume(dir_);
  ASSERT_TRUE(untouched);
  EXPECT_TRUE(untouched->first.repairs().empty());
}

TEST_F(RunDirectoryTest, ResumeTruncatesTheLogsToTheLastCheckpoint) {
  RunState state = two_pair_state();
  const IterationReport first = report_for(state, 0);
  const IterationReport second = report_for(state, 1);
  {
    RunDirectory dir = create_and_save(state);
    dir.append(first);
    state.next_iteration = 2;
    ASSERT_FALSE(dir.save(state));
    dir.append(second);  // a crash before the next checkpoint
    state.next_iteration = 3;
  }
  ASSERT_EQ(read(dir_ / kEventsFile), events_text(first) + events_text(second));

  Expected<std::pair<RunDirectory, RunState>> resumed = RunDirectory::resume(dir_);
  ASSERT_TRUE(resumed) << resumed.error();
  auto& [dir, restored] = *resumed;
  EXPECT_EQ(restored.next_iteration, 2);
  EXPECT_EQ(read(dir_ / kEventsFile), events_text(first));
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header() + stats_text(first));

  // the resumed run writes the iteration again, and the logs read as if nothing had happened
  dir.append(second);
  restored.next_iteration = 3;
  ASSERT_FALSE(dir.save(restored));
  EXPECT_EQ(read(dir_ / kEventsFile), events_text(first) + events_text(second));
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header() + stats_text(first) + stats_text(second));
  const pb::Checkpoint checkpoint = read_checkpoint(dir_ / kCheckpointFile);
  EXPECT_EQ(checkpoint.events_bytes(), static_cast<int64_t>(read(dir_ / kEventsFile).size()));
  EXPECT_EQ(checkpoint.next_iteration(), 3);
}

// annecs.csv gets a line per appended iteration; resume writes the state's lines again: cut back after a crash,
// rebuilt when damaged or missing, without a word in the repairs (the lines are the state's, like the pair files).
TEST_F(RunDirectoryTest, AnnecsLinesFollowTheState) {
  // pair 0 solved at 0 and retired at 2, its child (pair 1, created at 1) solved at 2
  RunState state = two_pair_state();
  state.pairs[0].first_solved_iteration = 0;
  state.pairs[0].retired_iteration = 2;
  state.pairs[1].first_solved_iteration = 2;
  state.next_iteration = 3;
  const std::string expected = annecs_header() + "0,0,0\n1,0,0\n2,1,1\n";
  EXPECT_EQ(annecs_text(state), expected);
  {
    RunDirectory dir = create_and_save(state);
    for (int t = 0; t < 3; ++t) {
      IterationReport report = report_for(state, t);
      report.annecs = annecs_at(state, t);
      dir.append(report);
    }
    ASSERT_FALSE(dir.save(state));
    EXPECT_EQ(read(dir_ / kAnnecsFile), expected);
    IterationReport lost = report_for(state, 3);  // a crash before its checkpoint
    lost.annecs = {2, 1};
    dir.append(lost);
  }
  EXPECT_EQ(read(dir_ / kAnnecsFile), expected + "3,2,1\n");
  for (const std::string& damage : {std::string("keep"), std::string("0,0,0\n"), std::string()}) {
    if (damage != "keep") write(dir_ / kAnnecsFile, damage);
    if (damage.empty()) fs::remove(dir_ / kAnnecsFile);
    const auto resumed = RunDirectory::resume(dir_);
    ASSERT_TRUE(resumed) << resumed.error();
    EXPECT_TRUE(resumed->first.repairs().empty());
    EXPECT_EQ(read(dir_ / kAnnecsFile), expected) << "after " << (damage.empty() ? "removal" : damage);
  }
}

TEST_F(RunDirectoryTest, StatsRowsRoundTripAndQuote) {
  PairStatsRow row;
  row.iteration = 3;
  row.pair = 2;
  row.env = "a,\"b\"";
  row.score = 0.1;
  row.finished = true;
  row.eval_steps = 97;
  row.best_score = 1.0 / 3;
  row.es_steps = 4;
  row.lr = 0.009999000000000001;
  row.sigma = -0.0;
  row.run_rollouts = 1234;
  row.run_env_steps = 9'876'543'210;
  row.pair_env_steps = 1'234'567'890;
  EXPECT_EQ(pair_stats_row(row),
            "3,2,\"a,\"\"b\"\"\",0.1,true,97,0.3333333333333333,false,4,0.009999000000000001,-0,0,0,0,0,"
            "1234,9876543210,1234567890\n");
  const std::string header = pair_stats_header();
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), 17);
}

TEST_F(RunDirectoryTest, RetiredPairPoliciesAreWrittenOnceMore) {
  RunState state = two_pair_state();
  RunDirectory dir = create_and_save(state);
  const fs::path policy = dir_ / kPoliciesDir / "pair-1.json";

  state.pairs[1].retired_iteration = 1;
  state.pairs[1].latest_score = 5;
  ASSERT_FALSE(dir.save(state));
  EXPECT_EQ(read(policy), policy_json_text(state.pairs[1].theta, 5.0));

  state.pairs[1].latest_score = 6;  // never happens to a retired pair; shows the file is left alone
  ASSERT_FALSE(dir.save(state));
  EXPECT_EQ(read(policy), policy_json_text(state.pairs[1].theta, 5.0));
}

TEST_F(RunDirectoryTest, NewPairsGetTheirEnvironmentFile) {
  RunState state = two_pair_state();
  RunDirectory dir = create_and_save(state);
  state.pairs.push_back(make_pair(2));
  state.pairs[2].parent_id = 0;
  state.pairs[2].created_iteration = 1;
  state.next_pair_id = 3;
  ASSERT_FALSE(dir.save(state));
  EXPECT_EQ(read(dir_ / kEnvsDir / "pair-2.env.json"), env_def_json_text(state.pairs[2].env));
  EXPECT_TRUE(fs::exists(dir_ / kPoliciesDir / "pair-2.best.json"));
}

TEST_F(RunDirectoryTest, DamagedRunsGiveErrorsNotCrashes) {
  const RunState state = two_pair_state();
  { RunDirectory dir = create_and_save(state); }
  const std::string good = read(dir_ / kCheckpointFile);
  const fs::path checkpoint = dir_ / kCheckpointFile;

  auto resume_error = [&]() {
    const auto resumed = RunDirectory::resume(dir_);
    EXPECT_FALSE(resumed);
    return resumed.error();
  };

  write(checkpoint, "this is not a checkpoint at all \xff\xff\xff\xff\xff");
  std::string error = resume_error();
  EXPECT_TRUE(contains(error, checkpoint.string())) << error;
  EXPECT_TRUE(contains(error, "corrupt")) << error;

  write(checkpoint, good.substr(0, good.size() / 2));
  error = resume_error();
  EXPECT_TRUE(contains(error, checkpoint.string())) << error;

  write(checkpoint, "");
  error = resume_error();
  EXPECT_TRUE(contains(error, checkpoint.string())) << error;

  // a byte flipped inside the body
  std::string flipped = good;
  flipped[flipped.size() / 2] ^= 0x10;
  write(checkpoint, flipped);
  error = resume_error();
  EXPECT_TRUE(contains(error, checkpoint.string() + ": checksum mismatch")) << error;

  // a valid message whose state is not: a pair with a short θ
  pb::Checkpoint message = *decode_checkpoint_file(good);
  message.mutable_pairs(1)->mutable_theta()->Truncate(3);
  write(checkpoint, encode_checkpoint_file(message));
  error = resume_error();
  EXPECT_TRUE(contains(error, "pairs[1].theta: 3 values, expected 2804")) << error;

  // a log that lost lines the checkpoint counts
  message = *decode_checkpoint_file(good);
  message.set_stats_bytes(message.stats_bytes() + 10);
  write(checkpoint, encode_checkpoint_file(message));
  error = resume_error();
  EXPECT_TRUE(contains(error, kStatsFile)) << error;
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header());

  fs::remove(checkpoint);
  error = resume_error();
  EXPECT_TRUE(contains(error, "does not exist")) << error;

  // a symbolic-link loop in its place is named as such, not as a missing checkpoint
  fs::create_symlink(dir_ / "loop", checkpoint);
  fs::create_symlink(checkpoint, dir_ / "loop");
  error = resume_error();
  EXPECT_TRUE(contains(error, "cannot access")) << error;
  EXPECT_FALSE(contains(error, "does not exist")) << error;
  fs::remove(dir_ / "loop");
  fs::remove(checkpoint);

  const auto missing = RunDirectory::resume(root_ / "nowhere");
  ASSERT_FALSE(missing);
  EXPECT_TRUE(contains(missing.error(), "nowhere")) << missing.error();
}

TEST_F(RunDirectoryTest, OneOwnerAtATime) {
  const RunState state = two_pair_state();
  RunDirectory owner = create_and_save(state);
  const std::string in_use = "is in use by another process (pid " + std::to_string(::getpid()) + ")";

  const Expected<RunDirectory> second = RunDirectory::create(dir_, small_config());
  ASSERT_FALSE(second);
  EXPECT_TRUE(contains(second.error(), in_use)) << second.error();
  const auto resumed = RunDirectory::resume(dir_);
  ASSERT_FALSE(resumed);
  EXPECT_TRUE(contains(resumed.error(), in_use)) << resumed.error();

  // the owner's files are untouched, and once it is gone the directory can be resumed
  const std::string events = read(dir_ / kEventsFile);
  { RunDirectory gone = std::move(owner); }
  EXPECT_EQ(read(dir_ / kEventsFile), events);
  const auto after = RunDirectory::resume(dir_);
  EXPECT_TRUE(after) << after.error();
}

TEST_F(RunDirectoryTest, ALockFileLeftByADeadProcessDoesNotBlock) {
  fs::create_directories(dir_);
  write(dir_ / kLockFile, "999999999\n");  // a pid no process has: the kernel holds no lock for it
  const Expected<RunDirectory> dir = RunDirectory::create(dir_, small_config());
  ASSERT_TRUE(dir) << dir.error();
  EXPECT_EQ(read(dir_ / kLockFile), std::to_string(::getpid()) + "\n");
}

// A file-size limit below the checkpoint's size and above a policy file's makes the checkpoint's write fail the
// way a full disk does (EFBIG instead of ENOSPC).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    ::getrlimit(RLIMIT_FSIZE, &previous_);
    rlimit limit = previous_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &previous_);
    std::signal(SIGXFSZ, previous_handler_);
  }

 private:
  rlimit previous_{};
  void (*previous_handler_)(int) = nullptr;
};

TEST_F(RunDirectoryTest, PairFilesNeverRunAheadOfTheCheckpoint) {
  RunState state = two_pair_state();
  RunDirectory dir = create_and_save(state);
  const std::string checkpoint = read(dir_ / kCheckpointFile);
  const fs::path policy = dir_ / kPoliciesDir / "pair-0.json";
  const std::string saved_policy = read(policy);
  ASSERT_GT(checkpoint.size(), 150'000u);
  ASSERT_LT(saved_policy.size(), 100'000u);

  state.pairs[0].theta[0] += 1;
  state.pairs[0].latest_score += 1;
  state.next_iteration = 2;
  {
    const FileSizeLimit limit(100'000);
    const std::optional<std::string> error = dir.save(state);
    ASSERT_TRUE(error) << "the save succeeded despite the file-size limit";
    EXPECT_TRUE(contains(*error, kCheckpointFile)) << *error;
  }
  EXPECT_EQ(read(dir_ / kCheckpointFile), checkpoint);
  EXPECT_EQ(read(policy), saved_policy);
  for (const auto& entry : fs::recursive_directory_iterator(dir_))
    EXPECT_FALSE(contains(entry.path().filename().string(), ".tmp")) << entry.path();
}

TEST_F(RunDirectoryTest, ResumeBringsPairFilesUpToTheCheckpoint) {
  const RunState state = two_pair_state();
  { RunDirectory dir = create_and_save(state); }
  // as a crash right after the checkpoint's rename leaves them: an old policy, a missing env file, a temporary
  const fs::path policy = dir_ / kPoliciesDir / "pair-1.json";
  const fs::path env = dir_ / kEnvsDir / "pair-1.env.json";
  const fs::path temporary = dir_ / kPoliciesDir / "pair-1.json.tmp.12345.0";
  write(policy, policy_json_text(make_pair(5).theta, 0.0));
  fs::remove(env);
  write(temporary, "[[0.1");

  const auto resumed = RunDirectory::resume(dir_);
  ASSERT_TRUE(resumed) << resumed.error();
  EXPECT_EQ(read(policy), policy_json_text(state.pairs[1].theta, state.pairs[1].latest_score));
  EXPECT_EQ(read(env), env_def_json_text(state.pairs[1].env));
  EXPECT_FALSE(fs::exists(temporary));
}

}  // namespace
}  // namespace poet
