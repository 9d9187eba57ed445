#pragma once
// The complete state of a run (spec §3 "State"): its settings, the archive of every pair ever created with its
// agent, optimizer and lineage, the iteration counter and run-wide counters. Everything a resume needs is here,
// and nothing else: random numbers are drawn by address (run seed, purpose, ids), so there is no generator state.

#include <cstdint>
#include <vector>

#include "engine/run_settings.h"
#include "simulation/envgen/env_encoding.h"
#include "simulation/es/optimizer.h"

namespace poet {

inline constexpr int kNone = -1;  // an absent pair id or iteration

// An accepted transfer into a pair.
struct TransferRecord {
  int iteration = 0;
  int source_pair = kNone;
  bool proposal = false;  // a one-step proposal from the source's θ, rather than its θ itself
  double score = 0;
  friend bool operator==(const TransferRecord&, const TransferRecord&) = default;
};

// An environment–agent pair, with its lineage (spec §3): parent, creation, the source of its first θ, accepted
// transfers, ES steps and first solve.
inline constexpr size_t kRecentScores = 5;  // Enhanced POET's transfer threshold: the best of the last five

struct Pair {
  int id = 0;
  EnvDef env;
  int created_iteration = 0;
  int parent_id = kNone;
  int initial_source_pair = kNone;  // whose θ it started from (kNone: a fresh θ)
  bool initial_by_proposal = false;
  double admission_score = 0;  // the score that admitted it (or its first evaluation for the first pair)

  std::vector<double> theta;
  OptimizerState optimizer;

  double latest_score = 0;  // the latest evaluation of θ on its own environment
  bool latest_finished = false;
  double best_score = 0;
  std::vector<double> best_theta;
  int best_iteration = kNone;

  int first_solved_iteration = kNone;  // sticky; frozen once retired
  int retired_iteration = kNone;       // kNone while active
  int64_t es_steps = 0;
  // The environment steps of its own ES steps: their perturbed rollouts and the evaluation after each (not
  // what it cost as a transfer target or source). A lineage's environment steps are summed from these.
  int64_t es_env_steps = 0;
  std::vector<TransferRecord> transfers;
  int64_t transfer_attempts = 0;  // transfer rounds this pair took part in as a target
  // The scores of its last kRecentScores evaluations, oldest first: the threshold of the threshold transfer test,
  // kept only when the run uses it (so other runs' states are unchanged).
  std::vector<double> recent_scores;

  bool active() const { return retired_iteration == kNone; }
  bool solved() const { return first_solved_iteration != kNone; }
};

struct RunCounters {
  int64_t rollouts = 0;
  int64_t env_steps = 0;
  int64_t transfer_attempts = 0;
  int64_t transfer_successes = 0;
  int64_t children_tried = 0;
  int64_t children_passed_mc = 0;
  int64_t children_admitted = 0;
  friend bool operator==(const RunCounters&, const RunCounters&) = default;
};

// One stage of the direct-path curriculum; the pair's environment is the last stage's.
struct CurriculumStage {
  EnvDef env;
  int started_iteration = 0;
  int solved_iteration = kNone;
};

struct RunState {
  RunSettings settings;    // made once from the run config (the config message itself is the run directory's)
  int next_iteration = 0;  // the iteration the run does next
  int next_pair_id = 0;
  std::vector<Pair> pairs;  // every pair ever created, in creation order (the archive)
  RunCounters counters;
  std::vector<CurriculumStage> stages;  // DIRECT_PATH only
  bool finished = false;                // a control's stopping rule was met

  // Indices into pairs of the active ones, in creation order.
  std::vector<size_t> active_indices() const;
  // The pair with this id, or nullptr.
  const Pair* find(int id) const;
};

}  // namespace poet
