// Tests run_directory/files/checkpoint.cpp: a hand-built state (retired and active pairs, transfers, curriculum
// stages, optimizer state, awkward doubles) survives the round trip bit for bit, and hostile checkpoints are
// refused with an error naming the field.

#include "run_directory/files/checkpoint.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "common/formats/envgen/env_proto.h"
#include "run_directory/config/run_config.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {
namespace {

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

std::vector<double> params(uint64_t id, double scale = 1.0) {
  RandomStream rng(stream_key(id, "checkpoint_test"));
  return random_params(rng, scale);
}

EnvDef stumps_env(uint32_t seed) {
  EnvDef def;
  def.encoding.name = "r0.3.b1.0_0.5_1.2";
  def.encoding.roughness = 0.1 + 0.2;
  def.encoding.stump_width = Interval{1.0, 2.0};
  def.encoding.stump_height = Interval{0.5, 1.2};
  def.encoding.stump_float = Interval{0.0, 1.0};
  def.seed = seed;
  return def;
}

Pair make_pair(int id, int created, EnvDef env) {
  Pair p;
  p.id = id;
  p.env = std::move(env);
  p.created_iteration = created;
  p.theta = params(static_cast<uint64_t>(id));
  p.theta[7] = -0.0;
  p.theta[8] = 5e-324;
  p.theta[9] = DBL_MAX;
  p.optimizer.m = params(100 + static_cast<uint64_t>(id), 1e-3);
  p.optimizer.v = params(200 + static_cast<uint64_t>(id), 1e-3);
  for (double& x : p.optimizer.v) x = x * x;
  p.optimizer.t = 17 + id;
  p.optimizer.lr = 0.01 * std::pow(0.9999, 17);
  p.optimizer.sigma = 0.1 / 3;
  p.latest_score = 123.456789012345678 + id;
  p.latest_finished = id % 2 == 0;
  p.best_score = 200.0 / 3;
  p.best_theta = params(300 + static_cast<uint64_t>(id));
  p.best_iteration = created + 1;
  p.es_steps = 40 - id;
  p.transfer_attempts = 3;
  return p;
}

// A POET state: three pairs with gaps in their ids, the first retired and solved, the second started by transfer
// of a proposal, the third with accepted transfers; every counter non-zero and agreeing with the pairs.
pb::RunConfig sample_config() {
  pb::RunConfig c;
  c.set_seed(7);
  c.set_iterations(100);
  c.mutable_es()->set_perturbations(4);
  c.mutable_poet()->set_mc_low(-1000);
  c.mutable_poet()->set_mutation_interval(10);
  c.mutable_poet()->set_transfer_interval(5);
  return c;
}

RunState sample_state() {
  RunState s;
  s.settings = run_settings(sample_config());
  s.next_iteration = 42;

  Pair first = make_pair(0, 0, EnvDef{EnvEncoding{}, 7});
  first.first_solved_iteration = 12;
  first.retired_iteration = 30;
  first.admission_score = -101.5;
  Pair second = make_pair(3, 10, stumps_env(999'999));
  second.parent_id = 0;
  second.initial_source_pair = 0;
  second.initial_by_proposal = true;
  second.admission_score = 31.25;
  Pair third = make_pair(5, 20, stumps_env(12));
  third.parent_id = 3;
  third.initial_source_pair = 3;
  third.transfers = {{25, 0, false, 1.0 / 7}, {40, 3, true, -0.0}};
  third.transfer_attempts = 5;
  s.pairs = {first, second, third};
  s.next_pair_id = 9;

  s.counters = {1'000'000'007, 123'456'789'012, 11, 2, 20, 9, 2};
  return s;
}

// A direct-path state: one pair at the second of two curriculum stages, finished.
pb::RunConfig direct_path_config() {
  pb::RunConfig c;
  c.set_mode(pb::RunConfig::DIRECT_PATH);
  c.set_seed(7);
  c.set_iterations(100);
  *c.mutable_direct_path()->mutable_target() = to_proto(stumps_env(7));
  c.mutable_direct_path()->set_budget_es_steps(50);
  return c;
}

RunState direct_path_state() {
  RunState s;
  s.settings = run_settings(direct_path_config());
  s.next_iteration = 42;
  Pair only = make_pair(0, 0, stumps_env(7));
  only.transfer_attempts = 0;
  s.pairs = {only};
  s.next_pair_id = 1;
  s.counters = {1'000'000'007, 123'456'789'012, 0, 0, 0, 0, 0};
  s.stages = {{EnvDef{EnvEncoding{}, 7}, 0, 15}, {stumps_env(7), 15, kNone}};
  s.finished = true;
  return s;
}

TEST(CheckpointTest, RoundTripIsExact) {
  const RunState state = sample_state();
  const pb::Checkpoint checkpoint = to_checkpoint(sample_config(), state);
  const Expected<RunState> restored = from_checkpoint(checkpoint);
  ASSERT_TRUE(restored) << restored.error();
  EXPECT_EQ(to_checkpoint(sample_config(), *restored).SerializeAsString(), checkpoint.SerializeAsString());

  // and field by field, for a readable failure
  ASSERT_EQ(restored->pairs.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const Pair& a = state.pairs[i];
    const Pair& b = restored->pairs[i];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.theta, b.theta);
    EXPECT_TRUE(std::signbit(b.theta[7]));
    EXPECT_EQ(a.best_theta, b.best_theta);
    EXPECT_EQ(a.optimizer, b.optimizer);
    EXPECT_EQ(a.transfers, b.transfers);
    EXPECT_EQ(a.env.encoding.name, b.env.encoding.name);
    EXPECT_TRUE(a.env.encoding.same_genes(b.env.encoding));
    EXPECT_EQ(a.env.seed, b.env.seed);
    EXPECT_EQ(a.retired_iteration, b.retired_iteration);
    EXPECT_EQ(a.first_solved_iteration, b.first_solved_iteration);
    EXPECT_EQ(a.parent_id, b.parent_id);
    EXPECT_EQ(a.initial_by_proposal, b.initial_by_proposal);
  }
  EXPECT_EQ(restored->counters, state.counters);
  EXPECT_EQ(restored->next_iteration, 42);
  EXPECT_EQ(restored->next_pair_id, 9);
}

// The threshold transfer test's recent scores travel with the pair.
TEST(CheckpointTest, RecentScoresRoundTrip) {
  pb::RunConfig config = sample_config();
  config.mutable_poet()->set_transfer_test(pb::THRESHOLD_TRANSFER_TEST);
  RunState state = sample_state();
  state.settings = run_settings(config);
  state.pairs[1].recent_scores = {12.5, -3, 240};
  const pb::Checkpoint checkpoint = to_checkpoint(config, state);
  const Expected<RunState> restored = from_checkpoint(checkpoint);
  ASSERT_TRUE(restored) << restored.error();
  EXPECT_EQ(restored->pairs[1].recent_scores, state.pairs[1].recent_scores);
  EXPECT_TRUE(restored->pairs[0].recent_scores.empty());
}

TEST(CheckpointTest, CurriculumRoundTripIsExact) {
  const pb::Checkpoint checkpoint = to_checkpoint(direct_path_config(), direct_path_state());
  const Expected<RunState> restored = from_checkpoint(checkpoint);
  ASSERT_TRUE(restored) << restored.error();
  EXPECT_EQ(to_checkpoint(direct_path_config(), *restored).SerializeAsString(), checkpoint.SerializeAsString());
  ASSERT_EQ(restored->stages.size(), 2u);
  EXPECT_EQ(restored->stages[0].solved_iteration, 15);
  EXPECT_EQ(restored->stages[1].solved_iteration, kNone);
  EXPECT_TRUE(restored->finished);

  pb::Checkpoint bad = checkpoint;
  bad.mutable_stages(1)->mutable_env()->set_seed(4'000'000'000u);
  const Expected<RunState> refused = from_checkpoint(bad);
  ASSERT_FALSE(refused);
  EXPECT_TRUE(contains(refused.error(), "stages[1].env.seed")) << refused.error();
}

TEST(CheckpointTest, EveryFieldIsWrittenEvenAtItsDefault) {
  // A default in the schema (parent_id = -1) must not hide a value: set fields make equal states equal bytes.
  const pb::Checkpoint checkpoint = to_checkpoint(direct_path_config(), direct_path_state());
  EXPECT_TRUE(checkpoint.pairs(0).has_parent_id());
  EXPECT_TRUE(checkpoint.pairs(0).has_initial_by_proposal());
  EXPECT_TRUE(checkpoint.has_finished());
  EXPECT_FALSE(checkpoint.has_events_bytes());  // the run directory's business
}

struct HostileCase {
  const char* name;
  std::function<void(pb::Checkpoint&)> damage;
  const char* expected;  // part of the error message
};

TEST(CheckpointTest, HostileCheckpointsNameTheField) {
  const std::vector<HostileCase> cases = {
      {"empty", [](pb::Checkpoint& c) { c.Clear(); }, "config: missing"},
      {"bad config", [](pb::Checkpoint& c) { c.mutable_config()->mutable_es()->set_perturbations(0); },
       "config.es.perturbations"},
      {"negative iteration", [](pb::Checkpoint& c) { c.set_next_iteration(-1); }, "next_iteration"},
      // the readers keep series per iteration: 2^31 − 1 would have them allocate without end
      {"iteration past any run", [](pb::Checkpoint& c) { c.set_next_iteration(2147483647); },
       "next_iteration: must be in [0, 10000000] (got 2147483647)"},
      {"no pairs", [](pb::Checkpoint& c) { c.clear_pairs(); }, "pairs: none"},
      {"short theta", [](pb::Checkpoint& c) { c.mutable_pairs(1)->mutable_theta()->Truncate(12); },
       "pairs[1].theta: 12 values, expected 2804"},
      {"long best theta", [](pb::Checkpoint& c) { c.mutable_pairs(2)->add_best_theta(1); },
       "pairs[2].best_theta: 2805 values, expected 2804"},
      {"nan theta",
       [](pb::Checkpoint& c) { c.mutable_pairs(0)->set_theta(5, std::numeric_limits<double>::quiet_NaN()); },
       "pairs[0].theta[5]: must be finite"},
      {"infinite best theta",
       [](pb::Checkpoint& c) { c.mutable_pairs(2)->set_best_theta(0, std::numeric_limits<double>::infinity()); },
       "pairs[2].best_theta[0]"},
      {"short moment", [](pb::Checkpoint& c) { c.mutable_pairs(1)->mutable_optimizer()->clear_m(); },
       "pairs[1].optimizer.m: 0 values, expected 2804"},
      {"negative second moment", [](pb::Checkpoint& c) { c.mutable_pairs(1)->mutable_optimizer()->set_v(3, -1); },
       "pairs[1].optimizer.v[3]"},
      {"nan sigma",
       [](pb::Checkpoint& c) {
         c.mutable_pairs(0)->mutable_optimizer()->set_sigma(std::numeric_limits<double>::quiet_NaN());
       },
       "pairs[0].optimizer.sigma"},
      {"missing optimizer", [](pb::Checkpoint& c) { c.mutable_pairs(2)->clear_optimizer(); },
       "pairs[2].optimizer: missing"},
      {"nan score",
       [](pb::Checkpoint& c) { c.mutable_pairs(2)->set_latest_score(std::numeric_limits<double>::quiet_NaN()); },
       "pairs[2].latest_score"},
      {"bad roughness",
       [](pb::Checkpoint& c) { c.mutable_pairs(1)->mutable_env()->mutable_encoding()->set_roughness(-1); },
       "pairs[1].env.encoding.roughness"},
      {"reversed interval",
       [](pb::Checkpoint& c) {
         c.mutable_pairs(2)->mutable_env()->mutable_encoding()->mutable_stump_height()->set_lo(5);
       },
       "pairs[2].env.encoding.stump_height"},
      {"seed out of range", [](pb::Checkpoint& c) { c.mutable_pairs(0)->mutable_env()->set_seed(1'000'000); },
       "pairs[0].env.seed"},
      {"missing env", [](pb::Checkpoint& c) { c.mutable_pairs(0)->clear_env(); }, "pairs[0].env: missing"},
      {"duplicate id", [](pb::Checkpoint& c) { c.mutable_pairs(2)->set_id(3); }, "pairs[2].id: 3 does not follow"},
      {"decreasing id", [](pb::Checkpoint& c) { c.mutable_pairs(1)->set_id(-4); }, "pairs[1].id"},
      {"next id taken", [](pb::Checkpoint& c) { c.set_next_pair_id(5); }, "next_pair_id: 5 must exceed"},
      {"unknown parent", [](pb::Checkpoint& c) { c.mutable_pairs(2)->set_parent_id(4); },
       "pairs[2].parent_id: no pair has id 4"},
      {"unknown transfer source",
       [](pb::Checkpoint& c) { c.mutable_pairs(2)->mutable_transfers(1)->set_source_pair(8); },
       "pairs[2].transfers[1].source_pair"},
      {"future retirement", [](pb::Checkpoint& c) { c.mutable_pairs(0)->set_retired_iteration(43); },
       "pairs[0].retired_iteration"},
      {"negative es steps", [](pb::Checkpoint& c) { c.mutable_pairs(1)->set_es_steps(-1); }, "pairs[1].es_steps"},
      {"negative counter", [](pb::Checkpoint& c) { c.mutable_counters()->set_env_steps(-5); }, "counters.env_steps"},
      {"recent scores under the full test", [](pb::Checkpoint& c) { c.mutable_pairs(1)->add_recent_scores(10); },
       "pairs[1].recent_scores: kept only under poet.transfer_test THRESHOLD_TRANSFER_TEST"},
      {"six recent scores",
       [](pb::Checkpoint& c) {
         for (int i = 0; i < 6; ++i) c.mutable_pairs(1)->add_recent_scores(i);
       },
       "pairs[1].recent_scores: 6 scores, at most 5"},
      {"nan recent score",
       [](pb::Checkpoint& c) { c.mutable_pairs(2)->add_recent_scores(std::numeric_limits<double>::quiet_NaN()); },
       "pairs[2].recent_scores[0]"},
  };
  const pb::Checkpoint good = to_checkpoint(sample_config(), sample_state());
  ASSERT_TRUE(from_checkpoint(good));
  for (const HostileCase& c : cases) {
    pb::Checkpoint bad = good;
    c.damage(bad);
    const Expected<RunState> state = from_checkpoint(bad);
    ASSERT_FALSE(state) << c.name;
    EXPECT_TRUE(contains(state.error(), c.expected)) << c.name << ": " << state.error();
  }
}

}  // namespace
}  // namespace poet
