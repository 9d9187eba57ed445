#pragma once
// What one iteration produced for the run directory: its events (pair created or retired, transfers, solves,
// curriculum stages; as values, run_event.h), one statistics row per pair that took an ES step, and ANNECS at its
// end. Deterministic: no wall-clock times, so a resumed run writes the same bytes as an uninterrupted one.

#include <cstdint>
#include <string>
#include <vector>

#include "engine/annecs.h"
#include "engine/run_event.h"

namespace poet {

struct PairStatsRow {
  int iteration = 0;
  int pair = 0;
  std::string env;   // the environment's name
  double score = 0;  // evaluation of the new θ on its own environment
  bool finished = false;
  int eval_steps = 0;  // steps of the evaluation episode (the first, when several)
  double best_score = 0;
  bool solved = false;
  int64_t es_steps = 0;
  double lr = 0;                 // after the step's decay
  double sigma = 0;              // the σ the step used (before its decay)
  double perturbation_mean = 0;  // mean return of the step's 2n perturbed rollouts
  double perturbation_max = 0;
  double grad_norm = 0;
  double theta_norm = 0;
  // the run's counters when this row's evaluation was done (the x axes of a learning curve)
  int64_t run_rollouts = 0;
  int64_t run_env_steps = 0;
  int64_t pair_env_steps = 0;  // the pair's es_env_steps after this step
};

struct IterationReport {
  int iteration = 0;
  std::vector<RunEvent> events;  // in the order they happened
  std::vector<PairStatsRow> stats;
  int64_t rollouts = 0;  // rollouts this iteration ran (for the progress display)
  Annecs annecs;         // both counts at the end of the iteration (annecs.csv)
};

}  // namespace poet
