#pragma once
// What the engine reports happened in an iteration, as values: pairs created, solved and retired, mutation
// attempts, reproductions, transfers and transfer rounds, and the direct path's stages. The engine builds no text;
// the run directory writes these as events.jsonl lines (run/event_json.h), in the order they happened.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "simulation/envgen/env_distance.h"

namespace poet {

// What an evaluation that solved a pair followed: its admission (the θ it was admitted with), one of its own ES
// steps, or an accepted transfer.
enum class SolvedBy { kAdmission, kOwnEs, kTransfer };

// A pair's first solve of its own environment.
struct SolvedEvent {
  int pair = 0;
  std::string env;
  double score = 0;
  int iterations_to_solve = 0;
  SolvedBy by = SolvedBy::kOwnEs;
};

// One mutation attempt of a reproduction: the child made from a parent, with the 5-vector the metrics read
// (spec §1.4); a duplicate of the archive, or the parent θ's minimal-criterion score on it and the verdict.
struct ChildEvent {
  int attempt = 0;
  int parent = 0;
  std::string env;
  EnvVector e{};
  bool duplicate = false;
  std::optional<double> mc_score;  // absent for a duplicate
  bool passed_mc = false;
};

// A child admitted: its environment, whose θ it started from, and what admitted it.
struct PairCreatedEvent {
  int pair = 0;
  std::string env;
  uint32_t seed = 0;
  int parent = 0;
  int source = 0;
  bool proposal = false;
  double score = 0;
  double novelty = 0;
};

// A reproduction's summary; with no eligible parent, only that.
struct ReproductionEvent {
  size_t eligible = 0;
  int tried = 0;
  int duplicates = 0;
  size_t passed_mc = 0;
  int admitted = 0;
  // PATA-EC novelty only: the evaluations the characterisations cost (every θ on every archived environment and
  // every child that passed the minimal criterion); absent otherwise, so other runs' event logs are unchanged.
  std::optional<size_t> pata_ec_evaluations;
};

struct PairRetiredEvent {
  int pair = 0;
  std::string env;
  bool solved = false;
};

// A transfer accepted into a target.
struct TransferEvent {
  int target = 0;
  int source = 0;
  bool proposal = false;
  double score = 0;
  double previous_score = 0;
};

// What a transfer round cost: the proposals it paid for out of the N(N−1) candidates, the rollouts it ran, and
// what it accepted.
struct TransferRoundEvent {
  bool full_test = true;
  size_t pairs = 0;
  size_t candidates = 0;
  size_t proposals = 0;
  int64_t accepted = 0;
  int64_t rollouts = 0;  // every episode of the round: direct evaluations, proposal ES steps and their evaluations
  std::optional<int64_t> unconfirmed;  // with confirm_transfers: choices that lost to θ on the fresh courses
};

// The direct path: a stage solved, or the next stage begun (its index, environment and distance to the target).
struct StageEvent {
  bool solved = false;  // stage_solved, else stage_advanced
  size_t stage = 0;
  std::string env;
  double distance_to_target = 0;
};

// A control's stopping rule met.
struct RunFinishedEvent {
  bool target_solved = false;  // else the budget was spent
  int64_t es_steps = 0;
};

using RunEvent = std::variant<SolvedEvent, ChildEvent, PairCreatedEvent, ReproductionEvent, PairRetiredEvent,
                              TransferEvent, TransferRoundEvent, StageEvent, RunFinishedEvent>;

}  // namespace poet
