#pragma once
// A run's settings as the engine reads them: typed, and made once from the run config by run_settings()
// (config/run_config.h), the one route from the config into the engine. Every value comes from the config, where
// a field left out holds the schema's default; the members' initialisers below only give a value before
// run_settings() sets them all (tests build settings by hand from them), never a run's default.

#include <cstdint>
#include <optional>
#include <string_view>

#include "simulation/envgen/env_distance.h"
#include "simulation/envgen/env_encoding.h"
#include "simulation/envgen/mutation.h"
#include "simulation/es/es_settings.h"
#include "simulation/walker/walker_env.h"

namespace poet {

enum class RunMode { kPoet, kPoetWithoutTransfer, kEsAlone, kDirectPath };
// The mode as a config names it ("POET", "POET_WITHOUT_TRANSFER", "ES_ALONE", "DIRECT_PATH"), for messages, and
// in words for people ("POET without transfer", "ES alone", "direct-path curriculum").
std::string_view mode_name(RunMode mode);
std::string_view mode_words(RunMode mode);
enum class ProposalKind { kAdam, kSgd };                        // the update Adam's next step would make, or SGD's
enum class TransferTest { kFull, kThreshold };                  // N(N−1) proposal steps a round, or Enhanced POET's
enum class ChildRanking { kNovelty, kLowestScoreFirst };        // the order admission walks the passing children in
enum class NoveltyMeasure { kEncodingDistance, kPataEc };       // 5-vectors' distance, or Enhanced POET's PATA-EC
enum class EnvironmentKind { kObstacleCourses, kCppnTerrain };  // what a POET run's first environment is
enum class ReproductionAgent { kCurrentTheta, kBestTheta };     // a pair's agent in reproduction and admission

// The episode settings every task of a run shares.
struct EpisodeSettings {
  WalkerOptions walker;
  int max_steps = 0;
  bool stochastic = false;
  int eval_episodes = 1;  // 1 unless stochastic
  // ES alone's domain randomisation (stochastic then too): each rollout's encoding drawn at this level
  std::optional<Difficulty> random_courses;
};

// The POET loop (spec §3); the fields of the schema's PoetConfig, every one set from it (run_directory/config): no
// defaults of its own, the schema's (proto/poet.proto) are the only ones.
struct PoetSettings {
  int mutation_interval = 0;
  int transfer_interval = 0;
  double repro_threshold = 0;
  int max_children = 0;
  int max_admitted = 0;
  double mc_low = 0;
  double mc_high = 0;
  int active_cap = 0;
  int novelty_k = 0;
  bool novelty_normalized = false;  // ENCODING_DISTANCE only
  NoveltyMeasure novelty{};
  ChildRanking child_ranking{};
  ProposalKind admission_proposal{};
  ProposalKind transfer_proposal{};
  double solved_score = 0;
  bool keep_admission_selection = false;
  TransferTest transfer_test{};
  EnvironmentKind environments{};
  ReproductionAgent reproduction_agent{};
  bool confirm_transfers = false;  // stochastic courses: the best candidate must beat θ again on fresh courses
  MutationOptions mutation;

  bool passes_mc(double score) const { return mc_low <= score && score <= mc_high; }
};

struct RunSettings {
  RunMode mode = RunMode::kPoet;
  uint64_t seed = 0;
  int iterations = 0;
  int checkpoint_interval = 0;
  bool init_zero = false;
  double init_stddev = 0;
  EsSettings es;
  EpisodeSettings episodes;
  PoetSettings poet;
  std::optional<EnvDef> target;   // the control's target: ES alone's environment, the direct path's end
  bool stop_when_solved = false;  // ES alone: stop once an evaluation solves the target
  double advance_threshold = 0;   // direct path: move to the next stage at this score
  int64_t budget_es_steps = 0;    // direct path: stop after this many ES steps
  int64_t env_step_budget = 0;    // stop after the iteration that reaches this many environment steps (0: none)
};

}  // namespace poet
