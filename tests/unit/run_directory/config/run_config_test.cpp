#include "run_directory/config/run_config.h"

#include <fcntl.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/formats/envgen/env_proto.h"
#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
using google::protobuf::util::MessageDifferencer;

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

// The presets live in the source tree; this file's own path locates it (no compile definition needed).
fs::path source_dir() {
  const std::string self = __FILE__;
  const size_t tests = self.rfind("/tests/unit/");
  EXPECT_NE(tests, std::string::npos) << self;
  return fs::path(self.substr(0, tests));
}
fs::path configs_dir() { return source_dir() / "deploy" / "configs"; }

pb::RunConfig load_preset(const std::string& name) {
  const Expected<pb::RunConfig> config = load_run_config((configs_dir() / name).string());
  EXPECT_TRUE(config) << config.error();
  return config ? *config : pb::RunConfig{};
}

// The error of a text that must be refused.
std::string error_of(const std::string& text) {
  const Expected<pb::RunConfig> config = parse_run_config(text);
  EXPECT_FALSE(config) << "accepted: " << text;
  return config.error();
}

// ------------------------------------------------------------------------------------------------ presets

TEST(RunConfig, EveryPresetParsesAndValidates) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(configs_dir())) {
    if (entry.path().extension() != ".textproto") continue;
    names.push_back(entry.path().filename().string());
    const Expected<pb::RunConfig> config = load_run_config(entry.path().string());
    EXPECT_TRUE(config) << config.error();
  }
  for (const char* expected :
       {"paper.textproto", "quick.textproto", "small.textproto", "challenging.textproto", "es_alone.textproto",
        "direct_path.textproto", "no_transfer.textproto", "enhanced.textproto", "deep.textproto"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected << " missing";
}

// The benchmark's workload (bench/run_es_workload.sh) is a config too.
TEST(RunConfig, BenchWorkloadParsesAndValidates) {
  const std::string path = (source_dir() / "bench" / "es_workload.textproto").string();
  const Expected<pb::RunConfig> config = load_run_config(path);
  ASSERT_TRUE(config) << config.error();
  EXPECT_EQ(config->es().perturbations(), 1024);
}

// The frontier probe of docs/results/deep-notebook.md (experiments/frontier_es.sh): ES alone on the deep run's pair
// 28's course, the preset's ES and three wider or larger searches, nothing else different.
TEST(RunConfig, FrontierEsConfigsDifferOnlyInTheirPopulationAndSigma) {
  const std::map<std::string, std::pair<int, double>> es = {// perturbations (half the rollouts a step), σ
                                                            {"A", {32, 0.05}},
                                                            {"B", {128, 0.05}},
                                                            {"C", {32, 0.1}},
                                                            {"D", {32, 0.2}}};
  std::vector<pb::RunConfig> configs;
  for (const auto& [setting, population_sigma] : es) {
    const std::string name = setting + "-28.textproto";
    const Expected<pb::RunConfig> config =
        load_run_config((source_dir() / "experiments" / "deep" / "frontier-es" / name).string());
    ASSERT_TRUE(config) << name << ": " << config.error();
    EXPECT_EQ(config->mode(), pb::RunConfig::ES_ALONE) << name;
    EXPECT_EQ(config->es().perturbations(), population_sigma.first) << name;
    EXPECT_EQ(config->es().init_sigma(), population_sigma.second) << name;
    configs.push_back(*config);
    configs.back().mutable_es()->clear_perturbations();
    configs.back().mutable_es()->clear_init_sigma();
  }
  for (const pb::RunConfig& c : configs) EXPECT_EQ(c.SerializeAsString(), configs[0].SerializeAsString());
}

// The σ comparison of docs/results/challenging.md: ES alone on one course from one seed, differing only in ES settings.
TEST(RunConfig, SigmaConfigsDifferOnlyInTheirEs) {
  std::vector<pb::RunConfig> configs;
  for (const auto& entry : fs::directory_iterator(source_dir() / "experiments" / "sigma")) {
    const Expected<pb::RunConfig> config = load_run_config(entry.path().string());
    ASSERT_TRUE(config) << config.error();
    EXPECT_EQ(config->mode(), pb::RunConfig::ES_ALONE) << entry.path();
    configs.push_back(*config);
  }
  ASSERT_EQ(configs.size(), 4u);
  for (pb::RunConfig& c : configs) c.clear_es();
  for (const pb::RunConfig& c : configs) EXPECT_EQ(c.SerializeAsString(), configs[0].SerializeAsString());
}

// The learning curves of docs/results/es-flat.md (experiments/learning_curve.sh): ES alone on flat from the same θ₀
// (seed 11), each with the population and learning rate that page gives it.
TEST(RunConfig, LearningCurveConfigsParseAndValidate) {
  const std::map<std::string, std::pair<int, double>> mirrored_pairs_and_lr = {
      {"experiments/curves/flat-64.textproto", {32, 0.02}},
      {"data/walkers/flat-walker.textproto", {64, 0.02}},
      {"experiments/curves/flat-512.textproto", {256, 0.01}},
      {"experiments/curves/flat-512-lr02.textproto", {256, 0.02}}};
  for (const auto& entry : fs::directory_iterator(source_dir() / "experiments" / "curves"))
    EXPECT_TRUE(mirrored_pairs_and_lr.count("experiments/curves/" + entry.path().filename().string()))
        << entry.path() << " is not listed here";
  for (const auto& [path, numbers] : mirrored_pairs_and_lr) {
    SCOPED_TRACE(path);
    const Expected<pb::RunConfig> config = load_run_config((source_dir() / path).string());
    ASSERT_TRUE(config) << config.error();
    EXPECT_EQ(config->mode(), pb::RunConfig::ES_ALONE);
    EXPECT_EQ(config->es_alone().target().encoding().name(), "flat");
    EXPECT_EQ(config->seed(), 11u);
    EXPECT_EQ(config->es().perturbations(), numbers.first);
    EXPECT_DOUBLE_EQ(config->es().init_lr(), numbers.second);
  }
}

TEST(RunConfig, PaperPresetHasThePapersNumbers) {
  const pb::RunConfig c = load_preset("paper.textproto");
  EXPECT_EQ(c.mode(), pb::RunConfig::POET);
  EXPECT_EQ(c.poet().active_cap(), 20);
  EXPECT_EQ(c.poet().mc_low(), 50);
  EXPECT_EQ(c.poet().mc_high(), 300);
  EXPECT_EQ(c.poet().max_children(), 512);
  EXPECT_EQ(c.poet().repro_threshold(), 200);
  EXPECT_EQ(c.es().perturbations(), 256);  // 512 rollouts per ES step
  EXPECT_EQ(c.iterations(), 25200);
  EXPECT_EQ(c.poet().solved_score(), 230);
  // Where the paper is silent the preset equals the reference, i.e. the schema default.
  EXPECT_EQ(c.seed(), pb::RunConfig{}.seed());
  EXPECT_EQ(c.poet().mutation_interval(), 200);
  EXPECT_EQ(c.poet().transfer_interval(), 25);
  EXPECT_EQ(c.es().init_sigma(), 0.1);
  EXPECT_EQ(c.es().init_lr(), 0.01);
  EXPECT_EQ(c.es().adam_epsilon(), 1e-8);
  EXPECT_EQ(c.walker().push_scale(), walker::kDefaultPushScale);  // the schema's default is the walker's
}

// Quick exists to show the loop at work within minutes: small populations, frequent reproduction and transfer.
TEST(RunConfig, QuickPresetIsSmall) {
  const pb::RunConfig c = load_preset("quick.textproto");
  EXPECT_EQ(c.mode(), pb::RunConfig::POET);
  EXPECT_LE(c.iterations(), 60);
  EXPECT_LE(c.es().perturbations(), 32);
  EXPECT_LE(c.poet().mutation_interval(), 10);
  EXPECT_LE(c.poet().transfer_interval(), 10);
  EXPECT_LT(c.poet().mutation_interval(), c.iterations());
  EXPECT_LE(c.poet().active_cap(), 6);
  EXPECT_GE(c.poet().max_admitted(), 1);
}

// The small preset keeps the paper's criteria and shrinks only the budget.
TEST(RunConfig, SmallPresetKeepsThePapersCriteria) {
  const pb::RunConfig c = load_preset("small.textproto");
  EXPECT_EQ(c.mode(), pb::RunConfig::POET);
  EXPECT_EQ(c.poet().repro_threshold(), 200);
  EXPECT_EQ(c.poet().mc_low(), 50);
  EXPECT_EQ(c.poet().mc_high(), 300);
  EXPECT_EQ(c.poet().solved_score(), 230);
  EXPECT_LE(c.es().perturbations(), 64);
  EXPECT_LE(c.poet().active_cap(), 5);
}

// The challenging preset keeps the paper's criteria, obstacle types and ranking; its ES and population are the ones
// docs/results/challenging.md names.
TEST(RunConfig, ChallengingPresetKeepsThePapersCriteria) {
  const pb::RunConfig c = load_preset("challenging.textproto");
  EXPECT_EQ(c.mode(), pb::RunConfig::POET);
  EXPECT_EQ(c.poet().repro_threshold(), 200);
  EXPECT_EQ(c.poet().mc_low(), 50);
  EXPECT_EQ(c.poet().mc_high(), 300);
  EXPECT_EQ(c.poet().solved_score(), 230);
  EXPECT_EQ(c.poet().child_ranking(), pb::NOVELTY);
  EXPECT_TRUE(c.poet().mutation().roughness() && c.poet().mutation().pits() && c.poet().mutation().stumps());
  EXPECT_TRUE(c.poet().mutation().all_types());
  EXPECT_EQ(c.es().perturbations(), 32);
  EXPECT_EQ(c.es().init_lr(), 0.01);
  EXPECT_EQ(c.es().init_sigma(), 0.05);
  EXPECT_EQ(c.poet().active_cap(), 6);
  EXPECT_EQ(c.poet().transfer_test(), pb::THRESHOLD_TRANSFER_TEST);
}

// Enhanced POET's three changes and its criteria, at the challenging preset's scale and start.
TEST(RunConfig, EnhancedPresetIsEnhancedPoet) {
  const pb::RunConfig c = load_preset("enhanced.textproto");
  const pb::RunConfig challenging = load_preset("challenging.textproto");
  EXPECT_EQ(c.mode(), pb::RunConfig::POET);
  EXPECT_EQ(c.poet().environments(), pb::CPPN_TERRAIN);
  EXPECT_EQ(c.poet().novelty(), pb::PATA_EC);
  EXPECT_EQ(c.poet().transfer_test(), pb::THRESHOLD_TRANSFER_TEST);
  EXPECT_EQ(c.poet().repro_threshold(), 200);
  EXPECT_EQ(c.poet().mc_low(), 25);
  EXPECT_EQ(c.poet().mc_high(), 340);
  EXPECT_EQ(c.seed(), challenging.seed());
  EXPECT_EQ(c.es().SerializeAsString(), challenging.es().SerializeAsString());
  for (auto field : {&pb::PoetConfig::mutation_interval, &pb::PoetConfig::transfer_interval,
                     &pb::PoetConfig::max_children, &pb::PoetConfig::max_admitted, &pb::PoetConfig::active_cap})
    EXPECT_EQ((c.poet().*field)(), (challenging.poet().*field)());
}

// The deep preset is the challenging one but for the changes it names: a longer life (active cap and mutation
// interval), normalised novelty and reproduction from the best θ; the paper's criteria stay.
TEST(RunConfig, DeepPresetDiffersFromChallengingOnlyWhereItSays) {
  pb::RunConfig c = load_preset("deep.textproto");
  pb::RunConfig challenging = load_preset("challenging.textproto");
  EXPECT_EQ(c.poet().active_cap(), 12);
  EXPECT_EQ(c.poet().mutation_interval(), 10);
  EXPECT_TRUE(c.poet().novelty_normalized());
  EXPECT_EQ(c.poet().reproduction_agent(), pb::BEST_THETA);
  EXPECT_EQ(c.poet().repro_threshold(), 200);
  EXPECT_EQ(c.poet().mc_low(), 50);
  EXPECT_EQ(c.poet().mc_high(), 300);
  EXPECT_EQ(c.poet().solved_score(), 230);
  for (pb::RunConfig* config : {&c, &challenging}) {
    config->clear_iterations();
    config->mutable_poet()->clear_active_cap();
    config->mutable_poet()->clear_mutation_interval();
    config->mutable_poet()->clear_novelty_normalized();
    config->mutable_poet()->clear_reproduction_agent();
  }
  EXPECT_EQ(c.SerializeAsString(), challenging.SerializeAsString());
}

TEST(RunConfig, StochasticPresetDiffersFromChallengingOnlyWhereItSays) {
  pb::RunConfig c = load_preset("stochastic.textproto");
  pb::RunConfig challenging = load_preset("challenging.textproto");
  EXPECT_TRUE(c.walker().stochastic_envs());
  EXPECT_EQ(c.walker().eval_episodes(), 5) << "the reference's";
  EXPECT_TRUE(c.poet().confirm_transfers());
  c.mutable_walker()->clear_stochastic_envs();
  if (c.walker().ByteSizeLong() == 0) c.clear_walker();
  c.mutable_poet()->clear_confirm_transfers();
  EXPECT_EQ(c.SerializeAsString(), challenging.SerializeAsString());
}

// The deep run's control without transfer and its second seed (experiments/deep/) are the preset but for the mode
// and the seed.
TEST(RunConfig, TheDeepRunsControlAndSecondSeedDifferOnlyWhereTheySay) {
  const pb::RunConfig deep = load_preset("deep.textproto");
  for (const auto& [file, change] : std::vector<std::pair<std::string, std::function<void(pb::RunConfig&)>>>{
           {"no-transfer.textproto", [](pb::RunConfig& c) { c.set_mode(pb::RunConfig::POET_WITHOUT_TRANSFER); }},
           {"seed-3.textproto", [](pb::RunConfig& c) { c.set_seed(3); }}}) {
    const Expected<pb::RunConfig> config = load_run_config((source_dir() / "experiments" / "deep" / file).string());
    ASSERT_TRUE(config) << config.error();
    pb::RunConfig expected = deep;
    change(expected);
    EXPECT_EQ(config->SerializeAsString(), expected.SerializeAsString()) << file;
  }
}

// The generalisation comparison (experiments/general/): POET on fixed and on stochastic courses are their presets
// but for the budget that ends them, and domain randomisation has the same ES and the same budget.
TEST(RunConfig, TheGeneralisationRunsDifferFromTheirPresetsOnlyByTheirBudget) {
  const auto general = [](const std::string& file) {
    const Expected<pb::RunConfig> c = load_run_config((source_dir() / "experiments" / "general" / file).string());
    EXPECT_TRUE(c) << file << ": " << (c ? "" : c.error());
    return c ? *c : pb::RunConfig();
  };
  const pb::RunConfig fixed = general("fixed.textproto");
  EXPECT_EQ(fixed.env_step_budget(), 100'000'000);
  for (const auto& [file, preset] : std::vector<std::pair<std::string, std::string>>{
           {"fixed.textproto", "challenging.textproto"}, {"stochastic.textproto", "stochastic.textproto"}}) {
    pb::RunConfig run = general(file);
    EXPECT_EQ(run.env_step_budget(), fixed.env_step_budget()) << file;
    run.clear_env_step_budget();
    run.clear_iterations();
    pb::RunConfig expected = load_preset(preset);
    expected.clear_iterations();
    EXPECT_EQ(run.SerializeAsString(), expected.SerializeAsString()) << file;
  }
  const pb::RunConfig dr = general("domain-randomisation.textproto");
  EXPECT_EQ(dr.mode(), pb::RunConfig::ES_ALONE);
  EXPECT_EQ(dr.es_alone().random_courses(), pb::EsAloneConfig::CHALLENGING_COURSES);
  EXPECT_EQ(dr.es().SerializeAsString(), fixed.es().SerializeAsString());
  EXPECT_EQ(dr.env_step_budget(), fixed.env_step_budget());
  EXPECT_EQ(dr.seed(), fixed.seed());
}

TEST(RunConfig, ControlPresetsHaveTheirModes) {
  const pb::RunConfig es_alone = load_preset("es_alone.textproto");
  EXPECT_EQ(es_alone.mode(), pb::RunConfig::ES_ALONE);
  const Expected<EnvDef> es_target = env_def_from_proto(es_alone.es_alone().target());
  ASSERT_TRUE(es_target) << es_target.error();
  EXPECT_EQ(es_target->seed, 0u);

  const pb::RunConfig direct = load_preset("direct_path.textproto");
  EXPECT_EQ(direct.mode(), pb::RunConfig::DIRECT_PATH);
  const Expected<EnvDef> direct_target = env_def_from_proto(direct.direct_path().target());
  ASSERT_TRUE(direct_target) << direct_target.error();
  EXPECT_TRUE(direct_target->encoding.has_pits());
  EXPECT_TRUE(direct_target->encoding.has_stumps());
  EXPECT_GT(direct_target->encoding.roughness, 0);
  EXPECT_GT(direct.direct_path().budget_es_steps(), 0);

  EXPECT_EQ(load_preset("no_transfer.textproto").mode(), pb::RunConfig::POET_WITHOUT_TRANSFER);
}

// ------------------------------------------------------------------------------------------------ defaults

TEST(RunConfig, DefaultsAreTheReferenceValues) {
  const Expected<pb::RunConfig> parsed = parse_run_config("mode: POET");
  ASSERT_TRUE(parsed) << parsed.error();
  const pb::RunConfig& c = *parsed;
  EXPECT_EQ(c.mode(), pb::RunConfig::POET);
  EXPECT_EQ(c.seed(), 24582922u);
  EXPECT_EQ(c.iterations(), 50000);
  EXPECT_EQ(c.init_stddev(), 0.1);
  EXPECT_FALSE(c.init_zero());
  EXPECT_EQ(c.es().perturbations(), 256);
  EXPECT_EQ(c.es().init_sigma(), 0.1);
  EXPECT_EQ(c.es().sigma_decay(), 0.999);
  EXPECT_EQ(c.es().sigma_floor(), 0.01);
  EXPECT_EQ(c.es().init_lr(), 0.01);
  EXPECT_EQ(c.es().lr_decay(), 0.9999);
  EXPECT_EQ(c.es().lr_floor(), 0.001);
  EXPECT_EQ(c.es().l2_coeff(), 0.01);
  EXPECT_EQ(c.es().adam_beta1(), 0.9);
  EXPECT_EQ(c.es().adam_beta2(), 0.999);
  EXPECT_EQ(c.es().adam_epsilon(), 1e-8);
  EXPECT_TRUE(c.es().normalize_grads_by_sigma());
  EXPECT_EQ(c.poet().mutation_interval(), 200);
  EXPECT_EQ(c.poet().transfer_interval(), 25);
  EXPECT_EQ(c.poet().repro_threshold(), 200);
  EXPECT_EQ(c.poet().max_children(), 8);
  EXPECT_EQ(c.poet().max_admitted(), 1);
  EXPECT_EQ(c.poet().mc_low(), 25);
  EXPECT_EQ(c.poet().mc_high(), 340);
  EXPECT_EQ(c.poet().active_cap(), 25);
  EXPECT_EQ(c.poet().novelty_k(), 5);
  EXPECT_FALSE(c.poet().novelty_normalized());
  EXPECT_EQ(c.poet().child_ranking(), pb::NOVELTY);
  EXPECT_EQ(c.poet().novelty(), pb::ENCODING_DISTANCE);
  EXPECT_EQ(c.poet().admission_proposal(), pb::SGD_PROPOSAL);
  EXPECT_EQ(c.poet().transfer_proposal(), pb::ADAM_PROPOSAL);
  EXPECT_EQ(c.poet().solved_score(), 230);
  EXPECT_EQ(c.walker().push_scale(), walker::kDefaultPushScale);  // the schema's default is the walker's
  EXPECT_EQ(c.walker().lidar(), pb::WalkerConfig::NEAREST);
  EXPECT_EQ(c.walker().max_steps(), 2000);
  EXPECT_EQ(c.walker().eval_episodes(), 5);
  EXPECT_FALSE(c.walker().stochastic_envs());
  EXPECT_EQ(c.direct_path().advance_threshold(), 200);
}

// The simulation's types take their defaults from the schema (a header generated from it at build time), so a
// config that names nothing and a default-constructed type agree, value for value.
TEST(RunConfig, TheTypesDefaultsAreTheSchemas) {
  const pb::RunConfig c;
  EXPECT_FALSE(validate(c).has_value()) << *validate(c);
  const RunSettings s = run_settings(c);
  EXPECT_TRUE(s.es == EsSettings{});
  const MutationOptions m = s.poet.mutation, want_m;
  EXPECT_EQ(m.roughness, want_m.roughness);
  EXPECT_EQ(m.pits, want_m.pits);
  EXPECT_EQ(m.stumps, want_m.stumps);
  EXPECT_EQ(m.stairs, want_m.stairs);
  EXPECT_EQ(m.mutate_stair_steps, want_m.mutate_stair_steps);
  EXPECT_EQ(m.all_types, want_m.all_types);
  const WalkerOptions w = s.episodes.walker, want_w;
  EXPECT_EQ(w.push_scale, want_w.push_scale);
  EXPECT_EQ(w.lidar, want_w.lidar);
  EXPECT_EQ(s.episodes.max_steps, walker::kDefaultTimeLimit);
  // the engine's settings have no defaults of their own: a config that names nothing carries the schema's
  EXPECT_EQ(s.poet.mutation_interval, c.poet().mutation_interval());
  EXPECT_EQ(s.poet.mc_high, c.poet().mc_high());
  EXPECT_EQ(s.poet.admission_proposal, ProposalKind::kSgd);  // SGD_PROPOSAL
  EXPECT_EQ(s.poet.transfer_proposal, ProposalKind::kAdam);  // ADAM_PROPOSAL
  EXPECT_EQ(s.poet.child_ranking, ChildRanking::kNovelty);
  EXPECT_EQ(s.poet.transfer_test, TransferTest::kFull);
  EXPECT_EQ(s.poet.novelty, NoveltyMeasure::kEncodingDistance);
  EXPECT_EQ(s.poet.reproduction_agent, ReproductionAgent::kCurrentTheta);
  EXPECT_EQ(s.poet.environments, EnvironmentKind::kObstacleCourses);
  // and the generated constants are the schema's declared defaults, exactly
  EXPECT_EQ(EsSettings{}.adam_epsilon, c.es().adam_epsilon());
  EXPECT_EQ(EsSettings{}.lr_decay, c.es().lr_decay());
  EXPECT_EQ(walker::kDefaultPushScale, c.walker().push_scale());
}

TEST(RunConfig, RunSettingsCarryEveryField) {
  const Expected<pb::RunConfig> c = parse_run_config(R"(
    mode: POET_WITHOUT_TRANSFER seed: 99 iterations: 321 checkpoint_interval: 4 init_zero: true init_stddev: 0.5
    es { perturbations: 3 init_sigma: 0.2 sigma_decay: 0.5 sigma_floor: 0.05 init_lr: 0.3 lr_decay: 0.25
         lr_floor: 0.125 l2_coeff: 0 adam_beta1: 0.5 adam_beta2: 0.75 adam_epsilon: 1e-4
         normalize_grads_by_sigma: false }
    poet { mutation_interval: 7 transfer_interval: 3 repro_threshold: 150 max_children: 4 max_admitted: 2
           mc_low: 10 mc_high: 300 active_cap: 6 novelty_k: 3 novelty_normalized: true
           child_ranking: LOWEST_SCORE_FIRST admission_proposal: ADAM_PROPOSAL transfer_proposal: SGD_PROPOSAL
           solved_score: 250 keep_admission_selection: true transfer_test: THRESHOLD_TRANSFER_TEST
           environments: CPPN_TERRAIN reproduction_agent: BEST_THETA
           mutation { roughness: false pits: false stumps: false stairs: true mutate_stair_steps: true
                      all_types: false } }
    walker { push_scale: 0 lidar: FIRST max_steps: 500 stochastic_envs: true eval_episodes: 3 }
  )");
  ASSERT_TRUE(c) << c.error();
  const RunSettings s = run_settings(*c);
  EXPECT_EQ(s.mode, RunMode::kPoetWithoutTransfer);
  EXPECT_EQ(mode_name(s.mode), "POET_WITHOUT_TRANSFER");
  EXPECT_EQ(mode_words(s.mode), "POET without transfer");
  EXPECT_EQ(s.seed, 99u);
  EXPECT_EQ(s.iterations, 321);
  EXPECT_EQ(s.checkpoint_interval, 4);
  EXPECT_TRUE(s.init_zero);
  EXPECT_EQ(s.init_stddev, 0.5);
  const EsSettings& es = s.es;
  EXPECT_EQ(es.perturbations, 3);
  EXPECT_EQ(es.init_sigma, 0.2);
  EXPECT_EQ(es.sigma_decay, 0.5);
  EXPECT_EQ(es.sigma_floor, 0.05);
  EXPECT_EQ(es.init_lr, 0.3);
  EXPECT_EQ(es.lr_decay, 0.25);
  EXPECT_EQ(es.lr_floor, 0.125);
  EXPECT_EQ(es.l2_coeff, 0);
  EXPECT_EQ(es.adam_beta1, 0.5);
  EXPECT_EQ(es.adam_beta2, 0.75);
  EXPECT_EQ(es.adam_epsilon, 1e-4);
  EXPECT_FALSE(es.normalize_grads_by_sigma);
  const PoetSettings& p = s.poet;
  EXPECT_EQ(p.mutation_interval, 7);
  EXPECT_EQ(p.transfer_interval, 3);
  EXPECT_EQ(p.repro_threshold, 150);
  EXPECT_EQ(p.max_children, 4);
  EXPECT_EQ(p.max_admitted, 2);
  EXPECT_EQ(p.mc_low, 10);
  EXPECT_EQ(p.mc_high, 300);
  EXPECT_TRUE(p.passes_mc(10) && p.passes_mc(300) && !p.passes_mc(300.5));
  EXPECT_EQ(p.active_cap, 6);
  EXPECT_EQ(p.novelty_k, 3);
  EXPECT_TRUE(p.novelty_normalized);
  EXPECT_EQ(p.child_ranking, ChildRanking::kLowestScoreFirst);
  EXPECT_EQ(p.admission_proposal, ProposalKind::kAdam);
  EXPECT_EQ(p.transfer_proposal, ProposalKind::kSgd);
  EXPECT_EQ(p.solved_score, 250);
  EXPECT_TRUE(p.keep_admission_selection);
  EXPECT_EQ(p.transfer_test, TransferTest::kThreshold);
  EXPECT_EQ(p.reproduction_agent, ReproductionAgent::kBestTheta);
  EXPECT_EQ(p.environments, EnvironmentKind::kCppnTerrain);
  const MutationOptions& m = p.mutation;
  EXPECT_FALSE(m.roughness);
  EXPECT_FALSE(m.pits);
  EXPECT_FALSE(m.stumps);
  EXPECT_TRUE(m.stairs);
  EXPECT_TRUE(m.mutate_stair_steps);
  EXPECT_FALSE(m.all_types);
  EXPECT_EQ(s.episodes.walker.push_scale, 0);
  EXPECT_EQ(s.episodes.walker.lidar, LidarRule::kFirst);
  EXPECT_EQ(s.episodes.max_steps, 500);
  EXPECT_TRUE(s.episodes.stochastic);
  EXPECT_EQ(s.episodes.eval_episodes, 3);
  EXPECT_FALSE(s.target);

  const Expected<pb::RunConfig> direct = parse_run_config(R"(
    mode: DIRECT_PATH
    direct_path { target { encoding { name: "r2" roughness: 2 } seed: 17 } advance_threshold: 180 budget_es_steps: 90 }
  )");
  ASSERT_TRUE(direct) << direct.error();
  const RunSettings d = run_settings(*direct);
  EXPECT_EQ(d.mode, RunMode::kDirectPath);
  EXPECT_EQ(mode_name(d.mode), "DIRECT_PATH");
  ASSERT_TRUE(d.target);
  EXPECT_EQ(d.target->seed, 17u);
  EXPECT_EQ(d.target->encoding.roughness, 2);
  EXPECT_EQ(d.advance_threshold, 180);
  EXPECT_EQ(d.budget_es_steps, 90);
  for (const auto mode : {pb::RunConfig::POET, pb::RunConfig::POET_WITHOUT_TRANSFER, pb::RunConfig::ES_ALONE,
                          pb::RunConfig::DIRECT_PATH}) {
    pb::RunConfig m = *direct;
    m.set_mode(mode);
    if (mode == pb::RunConfig::ES_ALONE) *m.mutable_es_alone()->mutable_target() = direct->direct_path().target();
    EXPECT_EQ(mode_name(run_settings(m).mode), pb::RunConfig::Mode_Name(mode));
  }
}

TEST(RunConfig, TheEnvStepBudgetAndDomainRandomisationReachTheSettings) {
  const Expected<pb::RunConfig> c = parse_run_config(R"(
    mode: ES_ALONE env_step_budget: 123456789
    es_alone { target { } random_courses: EXTREMELY_CHALLENGING_COURSES }
    walker { eval_episodes: 4 }
  )");
  ASSERT_TRUE(c) << c.error();
  const RunSettings s = run_settings(*c);
  EXPECT_EQ(s.env_step_budget, 123456789);
  EXPECT_EQ(s.episodes.random_courses, Difficulty::kExtremelyChallenging);
  EXPECT_TRUE(s.episodes.stochastic) << "domain randomisation draws a fresh seed too";
  EXPECT_EQ(s.episodes.eval_episodes, 4);
  const Expected<pb::RunConfig> easy =
      parse_run_config("mode: ES_ALONE es_alone { target { } random_courses: EASY_COURSES }");
  ASSERT_TRUE(easy) << easy.error();
  EXPECT_EQ(run_settings(*easy).episodes.random_courses, Difficulty::kEasy);
  const Expected<pb::RunConfig> fixed = parse_run_config("mode: ES_ALONE es_alone { target { } }");
  ASSERT_TRUE(fixed) << fixed.error();
  EXPECT_EQ(run_settings(*fixed).episodes.random_courses, std::nullopt);
  EXPECT_FALSE(run_settings(*fixed).episodes.stochastic);
  EXPECT_EQ(run_settings(*fixed).env_step_budget, 0);
  // random courses belong to ES alone
  EXPECT_NE(error_of("mode: POET es_alone { random_courses: EASY_COURSES }").find("es_alone"), std::string::npos);
  EXPECT_NE(error_of("env_step_budget: -1").find("env_step_budget"), std::string::npos);
  // stopping when solved needs a course of its own
  EXPECT_NE(error_of("mode: ES_ALONE es_alone { target { } random_courses: EASY_COURSES stop_when_solved: true }")
                .find("es_alone.stop_when_solved"),
            std::string::npos);
  const Expected<pb::RunConfig> stop =
      parse_run_config("mode: ES_ALONE es_alone { target { } stop_when_solved: true }");
  ASSERT_TRUE(stop) << stop.error();
  EXPECT_TRUE(run_settings(*stop).stop_when_solved);
}

TEST(RunConfig, ConfirmedTransfersNeedStochasticCourses) {
  EXPECT_EQ(error_of("mode: POET poet { confirm_transfers: true }"),
            "poet.confirm_transfers: true needs walker.stochastic_envs: true (on a fixed course a score is exact)");
  const Expected<pb::RunConfig> c =
      parse_run_config("mode: POET poet { confirm_transfers: true } walker { stochastic_envs: true }");
  ASSERT_TRUE(c) << c.error();
  EXPECT_TRUE(run_settings(*c).poet.confirm_transfers);
  EXPECT_EQ(error_of("mode: POET_WITHOUT_TRANSFER poet { confirm_transfers: true } walker { stochastic_envs: true }"),
            "poet.confirm_transfers: true contradicts mode POET_WITHOUT_TRANSFER (it applies to mode POET only, the "
            "one with transfer rounds)");
  EXPECT_FALSE(run_settings(*parse_run_config("mode: POET")).poet.confirm_transfers);
}

// RunSettingsCarryEveryField normalises the encoding distance, which PATA-EC refuses: the measure on its own.
TEST(RunConfig, RunSettingsCarryTheNoveltyMeasure) {
  const Expected<pb::RunConfig> pata = parse_run_config("poet { novelty: PATA_EC novelty_k: 3 }");
  ASSERT_TRUE(pata) << pata.error();
  EXPECT_EQ(run_settings(*pata).poet.novelty, NoveltyMeasure::kPataEc);
  EXPECT_EQ(run_settings(*pata).poet.novelty_k, 3);  // k is both measures'
  const Expected<pb::RunConfig> plain = parse_run_config("mode: POET");
  ASSERT_TRUE(plain) << plain.error();
  EXPECT_EQ(run_settings(*plain).poet.novelty, NoveltyMeasure::kEncodingDistance);
}

// ------------------------------------------------------------------------------------------------ parse errors

TEST(RunConfig, UnknownFieldIsRefusedByName) {
  const std::string top = error_of("seed: 3\nbogus_field: 1\n");
  EXPECT_TRUE(contains(top, "bogus_field")) << top;
  EXPECT_TRUE(top.starts_with("line 2:")) << top;
  const std::string nested = error_of("es {\n  sigma: 0.1\n}\n");
  EXPECT_TRUE(contains(nested, "sigma")) << nested;
  EXPECT_TRUE(nested.starts_with("line 2:")) << nested;
}

TEST(RunConfig, WrongTypeIsRefused) {
  for (const char* text : {"iterations: \"many\"", "es { perturbations: 1.5 }", "walker { stochastic_envs: 7 }",
                           "es { init_sigma: \"0.1\" }", "es: 3", "seed: -1", "iterations: 99999999999"}) {
    const std::string error = error_of(text);
    EXPECT_TRUE(error.starts_with("line 1:")) << text << " -> " << error;
  }
}

TEST(RunConfig, UnknownEnumValueIsRefused) {
  EXPECT_TRUE(contains(error_of("mode: POET_FOREVER"), "POET_FOREVER"));
  EXPECT_TRUE(error_of("mode: 7").starts_with("line 1:"));
  EXPECT_TRUE(contains(error_of("walker { lidar: FARTHEST }"), "FARTHEST"));
}

TEST(RunConfig, SyntaxErrorHasLineAndColumn) {
  const std::string error = error_of("seed: 1\n\nes {\n  perturbations: 4\n");
  EXPECT_TRUE(error.starts_with("line ")) << error;
  EXPECT_TRUE(error_of("es { perturbations 4 }").starts_with("line 1:"));
}

TEST(RunConfig, RepeatedSingularFieldIsRefused) {
  const std::string error = error_of("seed: 1\nseed: 2\n");
  EXPECT_TRUE(error.starts_with("line 2:")) << error;
  EXPECT_TRUE(contains(error, "seed")) << error;
}

TEST(RunConfig, CommentsAndNonAsciiInCommentsAreFine) {
  const Expected<pb::RunConfig> c = parse_run_config("# θ₀ ~ N(0, 0.1²), ≥ 230\nseed: 4  # × 2\n");
  ASSERT_TRUE(c) << c.error();
  EXPECT_EQ(c->seed(), 4u);
}

// ------------------------------------------------------------------------------------------------ validation

TEST(RunConfig, OutOfRangeNamesTheFieldAndValue) {
  EXPECT_EQ(error_of("es { init_sigma: -1 }"), "es.init_sigma: must be in (0, 10] (got -1)");
  EXPECT_EQ(error_of("es { perturbations: 0 }"), "es.perturbations: must be in [1, 100000] (got 0)");
  EXPECT_EQ(error_of("walker { push_scale: 1000.5 }"), "walker.push_scale: must be in [0, 1000] (got 1000.5)");
  EXPECT_EQ(error_of("es { adam_beta1: 1 }"), "es.adam_beta1: must be in [0, 1) (got 1)");
  EXPECT_EQ(error_of("es { lr_decay: 0 }"), "es.lr_decay: must be in (0, 1] (got 0)");
  EXPECT_EQ(error_of("es { init_lr: nan }"), "es.init_lr: must be a finite number (got nan)");

  const struct {
    const char* text;
    const char* path;
  } cases[] = {
      {"es { perturbations: 100001 }", "es.perturbations:"},
      {"es { init_sigma: 0 }", "es.init_sigma:"},
      {"es { init_sigma: inf }", "es.init_sigma:"},
      {"es { sigma_decay: 0 }", "es.sigma_decay:"},
      {"es { sigma_decay: 1.01 }", "es.sigma_decay:"},
      {"es { sigma_floor: -0.01 }", "es.sigma_floor:"},
      {"es { init_lr: 0 }", "es.init_lr:"},
      {"es { lr_decay: 2 }", "es.lr_decay:"},
      {"es { lr_floor: -1 }", "es.lr_floor:"},
      {"es { l2_coeff: -0.1 }", "es.l2_coeff:"},
      {"es { adam_beta1: -0.1 }", "es.adam_beta1:"},
      {"es { adam_beta2: 1 }", "es.adam_beta2:"},
      {"es { adam_epsilon: 0 }", "es.adam_epsilon:"},
      {"poet { mutation_interval: 0 }", "poet.mutation_interval:"},
      {"poet { transfer_interval: -5 }", "poet.transfer_interval:"},
      {"poet { repro_threshold: -inf }", "poet.repro_threshold:"},
      {"poet { max_children: -1 }", "poet.max_children:"},
      {"poet { max_admitted: -1 }", "poet.max_admitted:"},
      {"poet { mc_high: nan }", "poet.mc_high:"},
      {"poet { active_cap: 0 }", "poet.active_cap:"},
      {"poet { novelty_k: 0 }", "poet.novelty_k:"},
      {"poet { solved_score: inf }", "poet.solved_score:"},
      {"walker { push_scale: -1 }", "walker.push_scale:"},
      {"walker { max_steps: 0 }", "walker.max_steps:"},
      {"walker { max_steps: 100001 }", "walker.max_steps:"},
      {"walker { eval_episodes: 0 }", "walker.eval_episodes:"},
      {"walker { eval_episodes: 1001 }", "walker.eval_episodes:"},
      {"iterations: -1", "iterations:"},
      {"checkpoint_interval: 0", "checkpoint_interval:"},
      {"init_stddev: -0.1", "init_stddev:"},
      {"init_stddev: 10.5", "init_stddev:"},
  };
  for (const auto& c : cases) {
    const std::string error = error_of(c.text);
    EXPECT_TRUE(error.starts_with(c.path)) << c.text << " -> " << error;
    EXPECT_TRUE(contains(error, "(got ")) << c.text << " -> " << error;
  }
}

TEST(RunConfig, BoundaryValuesAreAccepted) {
  for (const char* text :
       {"es { perturbations: 1 }", "es { perturbations: 100000 } poet { active_cap: 7 }",
        "es { sigma_decay: 1 lr_decay: 1 }",
        "es { sigma_floor: 0 lr_floor: 0 l2_coeff: 0 adam_beta1: 0 adam_beta2: 0 }",
        "es { sigma_floor: 0.1 lr_floor: 0.01 }", "poet { max_children: 0 max_admitted: 0 }",
        "poet { mc_low: 100 mc_high: 100 }", "poet { active_cap: 1 novelty_k: 1 mutation_interval: 1 }",
        "walker { push_scale: 0 }", "walker { push_scale: 1000 max_steps: 100000 eval_episodes: 1000 }",
        "iterations: 0", "init_stddev: 0", "init_stddev: 10", "seed: 18446744073709551615",
        "mode: ES_ALONE es_alone { target { } } poet { mutation { roughness: false pits: false stumps: false } }"}) {
    const Expected<pb::RunConfig> c = parse_run_config(text);
    EXPECT_TRUE(c) << text << " -> " << c.error();
  }
}

// Every numeric field has an upper bound from its meaning (and scores a lower one): the bound itself is accepted,
// the next value beyond it refused with the field's path and the value. `$` in a text stands for the value.
TEST(RunConfig, EveryBoundIsExact) {
  const struct {
    const char* text;
    const char* path;
    const char* rule;
    const char* bound;   // accepted
    const char* beyond;  // refused, printed as in the message
  } cases[] = {
      {"iterations: $", "iterations", "must be in [0, 10000000]", "10000000", "10000001"},
      {"checkpoint_interval: $", "checkpoint_interval", "must be in [1, 1000000]", "1000000", "1000001"},
      {"env_step_budget: $", "env_step_budget", "must be in [0, 1000000000000000]", "1000000000000000",
       "1000000000000001"},
      {"init_stddev: $", "init_stddev", "must be in [0, 10]", "10", "10.000000000000002"},
      {"mode: ES_ALONE es_alone { target { } } es { perturbations: $ }", "es.perturbations", "must be in [1, 100000]",
       "100000", "100001"},
      {"es { init_sigma: $ }", "es.init_sigma", "must be in (0, 10]", "10", "10.000000000000002"},
      {"es { sigma_decay: $ }", "es.sigma_decay", "must be in (0, 1]", "1", "1.0000000000000002"},
      {"es { init_lr: $ }", "es.init_lr", "must be in (0, 1]", "1", "1.0000000000000002"},
      {"es { lr_decay: $ }", "es.lr_decay", "must be in (0, 1]", "1", "1.0000000000000002"},
      {"es { l2_coeff: $ }", "es.l2_coeff", "must be in [0, 1]", "1", "1.0000000000000002"},
      {"es { adam_beta1: $ }", "es.adam_beta1", "must be in [0, 1)", "0.9999999999999999", "1"},
      {"es { adam_beta2: $ }", "es.adam_beta2", "must be in [0, 1)", "0.9999999999999999", "1"},
      {"es { adam_epsilon: $ }", "es.adam_epsilon", "must be in (0, 1]", "1", "1.0000000000000002"},
      {"poet { mutation_interval: $ }", "poet.mutation_interval", "must be in [1, 1000000]", "1000000", "1000001"},
      {"poet { transfer_interval: $ }", "poet.transfer_interval", "must be in [1, 1000000]", "1000000", "1000001"},
      {"poet { max_children: $ }", "poet.max_children", "must be in [0, 10000]", "10000", "10001"},
      {"poet { max_admitted: $ }", "poet.max_admitted", "must be in [0, 10000]", "10000", "10001"},
      // one perturbation keeps a transfer round among 1000 pairs within the batch bound
      {"es { perturbations: 1 } poet { active_cap: $ }", "poet.active_cap", "must be in [1, 100]", "100", "101"},
      {"poet { novelty_k: $ }", "poet.novelty_k", "must be in [1, 1000]", "1000", "1001"},
      {"poet { repro_threshold: $ }", "poet.repro_threshold", "must be in [-10000, 10000]", "10000",
       "10000.000000000002"},
      {"poet { repro_threshold: $ }", "poet.repro_threshold", "must be in [-10000, 10000]", "-10000",
       "-10000.000000000002"},
      {"poet { mc_low: $ mc_high: 10000 }", "poet.mc_low", "must be in [-10000, 10000]", "10000", "10000.000000000002"},
      {"poet { mc_low: $ }", "poet.mc_low", "must be in [-10000, 10000]", "-10000", "-10000.000000000002"},
      {"poet { mc_high: $ }", "poet.mc_high", "must be in [-10000, 10000]", "10000", "10000.000000000002"},
      {"poet { mc_low: -10000 mc_high: $ }", "poet.mc_high", "must be in [-10000, 10000]", "-10000",
       "-10000.000000000002"},
      {"poet { solved_score: $ }", "poet.solved_score", "must be in [-10000, 10000]", "10000", "10000.000000000002"},
      {"poet { solved_score: $ }", "poet.solved_score", "must be in [-10000, 10000]", "-10000", "-10000.000000000002"},
      {"walker { push_scale: $ }", "walker.push_scale", "must be in [0, 1000]", "1000", "1000.0000000000001"},
      {"walker { max_steps: $ }", "walker.max_steps", "must be in [1, 100000]", "100000", "100001"},
      {"walker { eval_episodes: $ }", "walker.eval_episodes", "must be in [1, 1000]", "1000", "1001"},
      {"mode: DIRECT_PATH direct_path { target { } budget_es_steps: $ }", "direct_path.budget_es_steps",
       "must be in [1, 10000000000]", "10000000000", "10000000001"},
      {"mode: DIRECT_PATH direct_path { target { } budget_es_steps: 1 advance_threshold: $ }",
       "direct_path.advance_threshold", "must be in [-10000, 10000]", "10000", "10000.000000000002"},
      {"mode: DIRECT_PATH direct_path { target { } budget_es_steps: 1 advance_threshold: $ }",
       "direct_path.advance_threshold", "must be in [-10000, 10000]", "-10000", "-10000.000000000002"},
  };
  const auto with = [](std::string text, const std::string& value) { return text.replace(text.find('$'), 1, value); };
  for (const auto& c : cases) {
    const std::string at_bound = with(c.text, c.bound);
    const Expected<pb::RunConfig> accepted = parse_run_config(at_bound);
    EXPECT_TRUE(accepted) << at_bound << " -> " << accepted.error();
    EXPECT_EQ(error_of(with(c.text, c.beyond)), std::string(c.path) + ": " + c.rule + " (got " + c.beyond + ")");
  }
}

// The values of the report that passed validation and made θ non-finite or memory run out.
TEST(RunConfig, ReportedHostileValuesAreRefused) {
  EXPECT_EQ(error_of("es { l2_coeff: 1e300 }"), "es.l2_coeff: must be in [0, 1] (got 1e+300)");
  EXPECT_EQ(error_of("es { init_lr: 1e300 }"), "es.init_lr: must be in (0, 1] (got 1e+300)");
  EXPECT_EQ(error_of("es { init_sigma: 1e308 }"), "es.init_sigma: must be in (0, 10] (got 1e+308)");
  EXPECT_EQ(error_of("poet { max_children: 2000000000 }"), "poet.max_children: must be in [0, 10000] (got 2000000000)");
}

TEST(RunConfig, EsBatchOfAllPairsIsBounded) {
  // 2 · n · N rollouts in one batch: exactly 10^7 is accepted, one pair more is not
  const char* fits = "mode: POET_WITHOUT_TRANSFER es { perturbations: 100000 } poet { active_cap: 50 }";
  EXPECT_TRUE(parse_run_config(fits)) << parse_run_config(fits).error();
  EXPECT_EQ(error_of("mode: POET_WITHOUT_TRANSFER es { perturbations: 100000 } poet { active_cap: 51 }"),
            "es.perturbations: 2 · es.perturbations · poet.active_cap = 2 · 100000 · 51 = 10200000 rollouts in one "
            "batch, more than 10000000");
  // the same product in mode POET, named by the same rule before the transfer round's
  EXPECT_TRUE(error_of("es { perturbations: 100000 } poet { active_cap: 51 }").starts_with("es.perturbations: 2 ·"));
  // ES alone and the direct path run one pair: active_cap does not size their batches
  const char* one_pair = "mode: ES_ALONE es_alone { target { } } es { perturbations: 100000 } poet { active_cap: 100 }";
  EXPECT_TRUE(parse_run_config(one_pair)) << parse_run_config(one_pair).error();
}

TEST(RunConfig, TransferRoundBatchIsBounded) {
  // N · (N − 1) · (2n + e) rollouts in a transfer round's first batch (spec §3's job sizes)
  const char* fits = "es { perturbations: 504 } poet { active_cap: 100 }";  // 9989100
  EXPECT_TRUE(parse_run_config(fits)) << parse_run_config(fits).error();
  EXPECT_EQ(error_of("es { perturbations: 505 } poet { active_cap: 100 }"),
            "poet.active_cap: a transfer round of poet.active_cap · (poet.active_cap − 1) · (2 · es.perturbations + "
            "evaluation episodes) = 100 · 99 · (2 · 505 + 1) = 10008900 rollouts in one batch, more than 10000000");
  // stochastic courses evaluate each transfer over eval_episodes episodes
  EXPECT_TRUE(contains(error_of("es { perturbations: 504 } poet { active_cap: 100 } "
                                "walker { stochastic_envs: true eval_episodes: 5 }"),
                       "= 100 · 99 · (2 · 504 + 5) = 10028700 rollouts"));
  // no transfer, no transfer round
  const char* without = "mode: POET_WITHOUT_TRANSFER es { perturbations: 505 } poet { active_cap: 100 }";
  EXPECT_TRUE(parse_run_config(without)) << parse_run_config(without).error();
}

TEST(RunConfig, EmptyConfigMustSayMode) {
  const std::string message =
      "sets no field; an empty config would run every default (mode POET, 50000 iterations of the reference's "
      "settings) — write `mode: POET` to mean that";
  for (const char* text :
       {"", " \n\t\n", "# nothing but a comment\n", "# one\n\n  # two\n", "es { }", "poet { mutation { } } walker { }"})
    EXPECT_EQ(error_of(text), message) << "text: \"" << text << "\"";

  const Expected<pb::RunConfig> mode_only = parse_run_config("# the defaults, on purpose\nmode: POET\n");
  ASSERT_TRUE(mode_only) << mode_only.error();
  EXPECT_EQ(mode_only->iterations(), 50000);
  EXPECT_TRUE(parse_run_config("mode: POET_WITHOUT_TRANSFER"));
  const Expected<pb::RunConfig> seed_only = parse_run_config("seed: 3");
  ASSERT_TRUE(seed_only) << seed_only.error();
  EXPECT_EQ(seed_only->seed(), 3u);
  EXPECT_EQ(seed_only->mode(), pb::RunConfig::POET);
  // a value equal to its default is still a value the file sets
  EXPECT_TRUE(parse_run_config("es { init_lr: 0.01 }"));
  // a section of another mode is named as such, not as an empty config
  EXPECT_TRUE(error_of("direct_path { }").starts_with("direct_path:"));
}

TEST(RunConfig, FloorAboveItsInitialValueIsAContradiction) {
  EXPECT_EQ(error_of("es { sigma_floor: 0.5 }"), "es.sigma_floor: 0.5 exceeds es.init_sigma 0.1");
  EXPECT_EQ(error_of("es { init_lr: 0.001 lr_floor: 0.002 }"), "es.lr_floor: 0.002 exceeds es.init_lr 0.001");
}

TEST(RunConfig, McLowAboveMcHighIsAContradiction) {
  EXPECT_EQ(error_of("poet { mc_low: 300 mc_high: 50 }"), "poet.mc_low: 300 exceeds poet.mc_high 50");
}

TEST(RunConfig, PoetModesNeedAMutableGeneType) {
  const char* none = "poet { mutation { roughness: false pits: false stumps: false stairs: false } }";
  const std::string poet = error_of(none);
  EXPECT_TRUE(poet.starts_with("poet.mutation:")) << poet;
  EXPECT_TRUE(contains(poet, "POET")) << poet;
  const std::string no_transfer = error_of(std::string("mode: POET_WITHOUT_TRANSFER ") + none);
  EXPECT_TRUE(no_transfer.starts_with("poet.mutation:")) << no_transfer;
  // One type is enough, and CPPN terrain's mutation does not read them.
  EXPECT_TRUE(parse_run_config("poet { mutation { roughness: false pits: false stumps: false stairs: true } }"));
  EXPECT_TRUE(parse_run_config(std::string("poet { environments: CPPN_TERRAIN novelty: PATA_EC ") + (none + 7)));
  EXPECT_TRUE(error_of("poet { environments: CPPN_TERRAIN }").starts_with("poet.environments: CPPN_TERRAIN with"));
  EXPECT_EQ(error_of("poet { novelty: PATA_EC child_ranking: LOWEST_SCORE_FIRST }"),
            "poet.novelty: PATA_EC pays for evaluations that poet.child_ranking LOWEST_SCORE_FIRST never reads");
}

TEST(RunConfig, CppnTargetsForEsAloneButNotTheDirectPath) {
  const std::string cppn = R"(target { encoding { cppn {
      nodes { id: 0 role: INPUT } nodes { id: 1 role: OUTPUT bias: 0.1 }
      connections { from_node: 0 to_node: 1 weight: 0.5 } } } seed: 3 })";
  const Expected<pb::RunConfig> es_alone = parse_run_config("mode: ES_ALONE es_alone { " + cppn + " }");
  ASSERT_TRUE(es_alone) << es_alone.error();
  const RunSettings s = run_settings(*es_alone);
  ASSERT_TRUE(s.target->encoding.is_cppn());
  EXPECT_EQ(s.target->encoding.cppn->connections[0].weight, 0.5);
  EXPECT_EQ(error_of("mode: DIRECT_PATH direct_path { " + cppn + " budget_es_steps: 1 }"),
            "direct_path.target: a CPPN course has no direct path from flat (use an obstacle encoding)");
  const std::string cycle = error_of(R"(mode: ES_ALONE es_alone { target { encoding { cppn {
      nodes { id: 0 role: INPUT } nodes { id: 1 role: OUTPUT } nodes { id: 2 activation: SIN }
      connections { from_node: 0 to_node: 1 weight: 1 } connections { from_node: 1 to_node: 2 weight: 1 }
      connections { from_node: 2 to_node: 1 weight: 1 } } } } })");
  EXPECT_EQ(cycle, "es_alone.target.encoding.cppn.connections: they form a cycle");
}

TEST(RunConfig, SectionOfAnotherModeIsAContradiction) {
  const std::string es_alone = error_of("es_alone { target { seed: 1 } }");
  EXPECT_TRUE(es_alone.starts_with("es_alone:")) << es_alone;
  EXPECT_TRUE(contains(es_alone, "mode")) << es_alone;
  EXPECT_TRUE(contains(es_alone, "ES_ALONE")) << es_alone;

  const std::string direct = error_of("mode: ES_ALONE es_alone { target { } } direct_path { budget_es_steps: 5 }");
  EXPECT_TRUE(direct.starts_with("direct_path:")) << direct;
  EXPECT_TRUE(contains(direct, "mode is ES_ALONE")) << direct;

  // Even an empty section counts as given.
  EXPECT_TRUE(error_of("direct_path { }").starts_with("direct_path:"));
}

TEST(RunConfig, KeepAdmissionSelectionOnlyWithoutTransfer) {
  for (const char* mode :
       {"POET", "ES_ALONE es_alone { target { } }", "DIRECT_PATH direct_path { target { } budget_es_steps: 1 }"}) {
    const std::string error = error_of(std::string("mode: ") + mode + " poet { keep_admission_selection: true }");
    EXPECT_TRUE(error.starts_with("poet.keep_admission_selection:")) << error;
    EXPECT_TRUE(contains(error, "mode")) << error;
  }
  EXPECT_TRUE(parse_run_config("mode: POET_WITHOUT_TRANSFER poet { keep_admission_selection: true }"));
  EXPECT_TRUE(parse_run_config("poet { keep_admission_selection: false }"));
}

TEST(RunConfig, NormalizedNoveltyOnlyWithTheEncodingDistance) {
  EXPECT_EQ(error_of("poet { novelty: PATA_EC novelty_normalized: true }"),
            "poet.novelty_normalized: true contradicts poet.novelty PATA_EC (it applies to ENCODING_DISTANCE only)");
  EXPECT_TRUE(parse_run_config("poet { novelty: ENCODING_DISTANCE novelty_normalized: true }"));
  EXPECT_TRUE(parse_run_config("poet { novelty: PATA_EC novelty_normalized: false }"));
}

TEST(RunConfig, ModeRequirements) {
  EXPECT_EQ(error_of("mode: ES_ALONE"), "es_alone.target: required in mode ES_ALONE");
  EXPECT_EQ(error_of("mode: ES_ALONE es_alone { }"), "es_alone.target: required in mode ES_ALONE");
  EXPECT_EQ(error_of("mode: DIRECT_PATH direct_path { budget_es_steps: 10 }"),
            "direct_path.target: required in mode DIRECT_PATH");
  EXPECT_EQ(error_of("mode: DIRECT_PATH direct_path { target { } }"),
            "direct_path.budget_es_steps: required in mode DIRECT_PATH");
  EXPECT_EQ(error_of("mode: DIRECT_PATH direct_path { target { } budget_es_steps: 0 }"),
            "direct_path.budget_es_steps: must be in [1, 10000000000] (got 0)");
  EXPECT_TRUE(error_of("mode: DIRECT_PATH direct_path { target { } budget_es_steps: 5 advance_threshold: nan }")
                  .starts_with("direct_path.advance_threshold:"));
  EXPECT_TRUE(parse_run_config("mode: ES_ALONE es_alone { target { seed: 3 } }"));
  EXPECT_TRUE(parse_run_config("mode: DIRECT_PATH direct_path { target { } budget_es_steps: 1 }"));
}

TEST(RunConfig, InvalidTargetNamesItsPath) {
  const std::string pits = error_of("mode: ES_ALONE es_alone { target { encoding { pit_gap { lo: 2 hi: 1 } } } }");
  EXPECT_TRUE(pits.starts_with("es_alone.target.encoding.pit_gap:")) << pits;
  EXPECT_TRUE(contains(pits, "(got [2, 1])")) << pits;
  const std::string seed = error_of("mode: DIRECT_PATH direct_path { target { seed: 1000000 } budget_es_steps: 1 }");
  EXPECT_EQ(seed, "direct_path.target.seed: must be < 1000000 (got 1000000)");
  const std::string rough =
      error_of("mode: DIRECT_PATH direct_path { target { encoding { roughness: -2 } } budget_es_steps: 1 }");
  EXPECT_TRUE(rough.starts_with("direct_path.target.encoding.roughness:")) << rough;
}

TEST(RunConfig, ValidateReportsTheFirstBadField) {
  pb::RunConfig c;
  c.mutable_es()->set_init_sigma(-1);
  c.mutable_walker()->set_max_steps(0);
  EXPECT_EQ(validate(c).value_or(""), "es.init_sigma: must be in (0, 10] (got -1)");
  c.mutable_es()->set_init_sigma(std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(validate(c).value_or("").starts_with("es.init_sigma: must be a finite number"));
  c.mutable_es()->clear_init_sigma();
  EXPECT_TRUE(validate(c).value_or("").starts_with("walker.max_steps:"));
}

// ------------------------------------------------------------------------------------------------ text round trip

void expect_round_trip(const pb::RunConfig& config) {
  const std::string text = run_config_text(config);
  const Expected<pb::RunConfig> back = parse_run_config(text);
  ASSERT_TRUE(back) << back.error() << "\n" << text;
  std::string diff;
  MessageDifferencer differencer;
  differencer.ReportDifferencesToString(&diff);
  EXPECT_TRUE(differencer.Compare(config, *back)) << diff << "\n" << text;
}

TEST(RunConfig, TextRoundTripsEveryPreset) {
  for (const auto& entry : fs::directory_iterator(configs_dir())) {
    if (entry.path().extension() != ".textproto") continue;
    SCOPED_TRACE(entry.path().string());
    const Expected<pb::RunConfig> config = load_run_config(entry.path().string());
    ASSERT_TRUE(config) << config.error();
    expect_round_trip(*config);
  }
}

TEST(RunConfig, TextRoundTripIsBitExact) {
  pb::RunConfig c;
  c.set_mode(pb::RunConfig::ES_ALONE);
  c.set_seed(std::numeric_limits<uint64_t>::max());
  c.set_init_stddev(0.1 + 0.2);
  c.mutable_es()->set_init_sigma(1.0 / 3.0);
  c.mutable_es()->set_sigma_floor(std::nextafter(0.01, 0.0));
  c.mutable_es()->set_l2_coeff(5e-324);  // the smallest subnormal
  c.mutable_es()->set_adam_epsilon(std::numeric_limits<double>::min());
  c.mutable_es()->set_sigma_decay(std::nextafter(1.0, 0.0));
  c.mutable_es()->set_init_lr(0.01);                        // explicitly set to the default: must stay set
  c.mutable_poet()->set_mc_low(-1e4);                       // the bound itself
  c.mutable_poet()->set_mc_high(std::nextafter(1e4, 0.0));  // just inside it
  c.mutable_poet()->set_repro_threshold(-0.0);
  c.mutable_walker()->set_push_scale(2.0 / 3.0);
  c.mutable_walker()->set_lidar(pb::WalkerConfig::FIRST);
  EnvDef target;
  target.encoding.name = "odd \"name\"\n";
  target.encoding.roughness = 0.1 + 0.7;
  target.encoding.pit_gap = Interval{1.0 / 7.0, 19.999999999999996};
  target.seed = 999'999;
  *c.mutable_es_alone()->mutable_target() = to_proto(target);
  ASSERT_FALSE(validate(c).has_value()) << *validate(c);

  expect_round_trip(c);
  const Expected<pb::RunConfig> back = parse_run_config(run_config_text(c));
  ASSERT_TRUE(back) << back.error();
  EXPECT_TRUE(back->es().has_init_lr());
  EXPECT_FALSE(back->es().has_lr_floor());
  EXPECT_EQ(back->es().l2_coeff(), 5e-324);
  EXPECT_TRUE(std::signbit(back->poet().repro_threshold()));
  EXPECT_EQ(back->es().sigma_decay(), std::nextafter(1.0, 0.0));
}

TEST(RunConfig, DefaultConfigPrintsEmpty) { EXPECT_EQ(run_config_text(pb::RunConfig{}), ""); }

// ------------------------------------------------------------------------------------------------ files

class RunConfigFile : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  poet::testing::ScratchDir scratch_;
  fs::path dir_ = scratch_.path();
};

TEST_F(RunConfigFile, LoadsAFile) {
  const Expected<pb::RunConfig> c = load_run_config(write("ok.textproto", "iterations: 7\n"));
  ASSERT_TRUE(c) << c.error();
  EXPECT_EQ(c->iterations(), 7);
}

TEST_F(RunConfigFile, ErrorsStartWithThePath) {
  const std::string missing = (dir_ / "missing.textproto").string();
  const Expected<pb::RunConfig> absent = load_run_config(missing);
  ASSERT_FALSE(absent);
  EXPECT_TRUE(absent.error().starts_with(missing + ": ")) << absent.error();

  const std::string bad = write("bad.textproto", "es {\n  nope: 1\n}\n");
  const Expected<pb::RunConfig> syntax = load_run_config(bad);
  ASSERT_FALSE(syntax);
  EXPECT_TRUE(syntax.error().starts_with(bad + ": line 2:")) << syntax.error();

  const std::string invalid = write("invalid.textproto", "es { init_sigma: -1 }\n");
  EXPECT_EQ(load_run_config(invalid).error(), invalid + ": es.init_sigma: must be in (0, 10] (got -1)");

  const std::string dir = dir_.string();
  EXPECT_TRUE(load_run_config(dir).error().starts_with(dir + ": ")) << load_run_config(dir).error();
}

TEST_F(RunConfigFile, RefusesAnEmptyFile) {
  const std::string empty = write("empty.textproto", "");
  const Expected<pb::RunConfig> c = load_run_config(empty);
  ASSERT_FALSE(c);
  EXPECT_TRUE(c.error().starts_with(empty + ": sets no field;")) << c.error();
}

TEST_F(RunConfigFile, RefusesAFifoWithoutWaiting) {
  const std::string fifo = (dir_ / "fifo.textproto").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  // no writer is opened unless the read is still blocked after 10 s, and then only to end the test
  auto read = std::async(std::launch::async, [&] { return load_run_config(fifo); });
  if (read.wait_for(std::chrono::seconds(10)) == std::future_status::timeout) {
    ADD_FAILURE() << "load_run_config blocked on a FIFO";
    while (read.wait_for(std::chrono::milliseconds(100)) == std::future_status::timeout) {
      const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
      if (fd >= 0) ::close(fd);
    }
  }
  const Expected<pb::RunConfig> c = read.get();
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error(), fifo + ": is not a regular file (a FIFO)");
}

TEST_F(RunConfigFile, RefusesAHugeFile) {
  const std::string huge = write("huge.textproto", std::string(kMaxRunConfigBytes + 1, '#'));
  const Expected<pb::RunConfig> c = load_run_config(huge);
  ASSERT_FALSE(c);
  EXPECT_TRUE(contains(c.error(), "larger than")) << c.error();
  EXPECT_FALSE(parse_run_config(std::string(kMaxRunConfigBytes + 1, ' ')));
}

}  // namespace
}  // namespace poet
