// Tests coordinator/run/run_directory.cpp: the files a run writes and their contents, refusing to start over an
// existing run, resume cutting the logs back to the last checkpoint, and damaged checkpoints giving errors.

#include "run/run_directory.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/run_config.h"
#include "envgen/env_json.h"
#include "poet/checkpoint.h"
#include "policy/mlp.h"
#include "policy/policy_file.h"
#include "rng.h"

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

RunState two_pair_state() {
  RunState state;
  state.config = small_config();
  state.pairs = {make_pair(0), make_pair(1)};
  state.next_pair_id = 2;
  return state;
}

// A report for iteration t with one event and one stats row per pair of the state.
IterationReport report_for(const RunState& state, int t) {
  IterationReport report;
  report.iteration = t;
  report.events.push_back({{"iteration", t}, {"event", "test"}, {"value", 0.1 * t}});
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
  for (const auto& e : report.events) text += e.dump() + "\n";
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
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() / ("poet_run_directory_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
    dir_ = root_ / "run";
  }
  void TearDown() override { fs::remove_all(root_); }

  // Creates the run and saves state; fails the test on any error.
  RunDirectory create_and_save(const RunState& state) {
    Expected<RunDirectory> dir = RunDirectory::create(dir_, state.config);
    EXPECT_TRUE(dir) << dir.error();
    if (!dir) throw std::runtime_error(dir.error());
    const auto error = dir->save(state);
    EXPECT_FALSE(error) << *error;
    return std::move(*dir);
  }

  fs::path root_;
  fs::path dir_;
};

TEST_F(RunDirectoryTest, CreateAndSaveWriteTheFiles) {
  const RunState state = two_pair_state();
  Expected<RunDirectory> dir = RunDirectory::create(dir_, state.config);
  ASSERT_TRUE(dir) << dir.error();
  EXPECT_EQ(dir->path(), dir_);
  EXPECT_FALSE(fs::exists(dir_ / kCheckpointFile));
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header());
  EXPECT_EQ(read(dir_ / kEventsFile), "");
  const Expected<pb::RunConfig> config = parse_run_config(read(dir_ / kConfigFile));
  ASSERT_TRUE(config) << config.error();
  EXPECT_EQ(config->SerializeAsString(), state.config.SerializeAsString());

  ASSERT_FALSE(dir->save(state));
  pb::Checkpoint checkpoint;
  ASSERT_TRUE(checkpoint.ParseFromString(read(dir_ / kCheckpointFile)));
  EXPECT_EQ(checkpoint.events_bytes(), 0);
  EXPECT_EQ(checkpoint.stats_bytes(), static_cast<int64_t>(pair_stats_header().size()));
  checkpoint.clear_events_bytes();
  checkpoint.clear_stats_bytes();
  EXPECT_EQ(checkpoint.SerializeAsString(), to_checkpoint(state).SerializeAsString());
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
  const Expected<RunDirectory> again = RunDirectory::create(dir_, state.config);
  ASSERT_FALSE(again);
  EXPECT_TRUE(contains(again.error(), "already holds a run; resume it or choose another directory")) << again.error();
  EXPECT_EQ(read(dir_ / kCheckpointFile), checkpoint);
}

TEST_F(RunDirectoryTest, CreateMayStartOverWhereNoCheckpointWasSaved) {
  {
    Expected<RunDirectory> dir = RunDirectory::create(dir_, small_config());
    ASSERT_TRUE(dir);
    dir->append(report_for(two_pair_state(), 0));
  }
  const Expected<RunDirectory> again = RunDirectory::create(dir_, small_config());
  ASSERT_TRUE(again) << again.error();
  EXPECT_EQ(read(dir_ / kEventsFile), "");
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header());
}

TEST_F(RunDirectoryTest, ResumeTruncatesTheLogsToTheLastCheckpoint) {
  RunState state = two_pair_state();
  const IterationReport first = report_for(state, 0);
  const IterationReport second = report_for(state, 1);
  {
    RunDirectory dir = create_and_save(state);
    dir.append(first);
    state.next_iteration = 1;
    ASSERT_FALSE(dir.save(state));
    dir.append(second);  // a crash before the next checkpoint
    state.next_iteration = 2;
  }
  ASSERT_EQ(read(dir_ / kEventsFile), events_text(first) + events_text(second));

  Expected<std::pair<RunDirectory, RunState>> resumed = RunDirectory::resume(dir_);
  ASSERT_TRUE(resumed) << resumed.error();
  auto& [dir, restored] = *resumed;
  EXPECT_EQ(restored.next_iteration, 1);
  EXPECT_EQ(read(dir_ / kEventsFile), events_text(first));
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header() + stats_text(first));

  // the resumed run writes the iteration again, and the logs read as if nothing had happened
  dir.append(second);
  restored.next_iteration = 2;
  ASSERT_FALSE(dir.save(restored));
  EXPECT_EQ(read(dir_ / kEventsFile), events_text(first) + events_text(second));
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header() + stats_text(first) + stats_text(second));
  pb::Checkpoint checkpoint;
  ASSERT_TRUE(checkpoint.ParseFromString(read(dir_ / kCheckpointFile)));
  EXPECT_EQ(checkpoint.events_bytes(), static_cast<int64_t>(read(dir_ / kEventsFile).size()));
  EXPECT_EQ(checkpoint.next_iteration(), 2);
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
  EXPECT_EQ(pair_stats_row(row),
            "3,2,\"a,\"\"b\"\"\",0.1,true,97,0.3333333333333333,false,4,0.009999000000000001,-0,0,0,0,0\n");
}

TEST_F(RunDirectoryTest, RetiredPairPoliciesAreWrittenOnceMore) {
  RunState state = two_pair_state();
  RunDirectory dir = create_and_save(state);
  const fs::path policy = dir_ / kPoliciesDir / "pair-1.json";

  state.pairs[1].retired_iteration = 0;
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

  write(checkpoint, "this is not a checkpoint \xff\xff\xff\xff\xff");
  std::string error = resume_error();
  EXPECT_TRUE(contains(error, checkpoint.string())) << error;
  EXPECT_TRUE(contains(error, "corrupt")) << error;

  write(checkpoint, good.substr(0, good.size() / 2));
  error = resume_error();
  EXPECT_TRUE(contains(error, checkpoint.string())) << error;

  write(checkpoint, "");
  error = resume_error();
  EXPECT_TRUE(contains(error, checkpoint.string())) << error;

  // a valid message whose state is not: a pair with a short θ
  pb::Checkpoint message;
  ASSERT_TRUE(message.ParseFromString(good));
  message.mutable_pairs(1)->mutable_theta()->Truncate(3);
  write(checkpoint, message.SerializeAsString());
  error = resume_error();
  EXPECT_TRUE(contains(error, "pairs[1].theta: 3 values, expected 2804")) << error;

  // a log that lost lines the checkpoint counts
  message.ParseFromString(good);
  message.set_stats_bytes(message.stats_bytes() + 10);
  write(checkpoint, message.SerializeAsString());
  error = resume_error();
  EXPECT_TRUE(contains(error, kStatsFile)) << error;
  EXPECT_EQ(read(dir_ / kStatsFile), pair_stats_header());

  fs::remove(checkpoint);
  error = resume_error();
  EXPECT_TRUE(contains(error, "does not exist")) << error;

  const auto missing = RunDirectory::resume(root_ / "nowhere");
  ASSERT_FALSE(missing);
  EXPECT_TRUE(contains(missing.error(), "nowhere")) << missing.error();
}

}  // namespace
}  // namespace poet
