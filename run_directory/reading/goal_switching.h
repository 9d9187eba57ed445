#pragma once
// Goal switching along a lineage (the paper credits it for solving what direct optimisation cannot): the chain of
// environments from the first one down to a pair's, parent by parent, and for each how its agent got there —
// where its first θ came from, which accepted transfers it took, and what solved it (its admission θ, its own ES
// step, or an accepted transfer), read from the run's checkpoint and events.

#include <string>
#include <vector>

#include "run_directory/reading/run_metrics.h"
#include "run_directory/reading/run_snapshot.h"

namespace poet {

enum class SolveCause {
  kNotSolved,
  kAdmission,  // the θ it was admitted with (its parent's, or another pair's through the admission walk)
  kOwnEs,      // the evaluation after one of its own ES steps
  kTransfer,   // an accepted transfer
};

struct LineageLink {
  int pair = 0;
  std::string env;
  int level = 0;  // Difficulty
  int created = 0;
  int parent = kNone;
  int first_theta_from = kNone;  // the pair whose θ it started from
  bool first_by_proposal = false;
  double admission_score = 0;
  int solved = kNone;  // first-solved iteration
  SolveCause cause = SolveCause::kNotSolved;
  int solved_by = kNone;                       // kAdmission: the θ's source pair; kTransfer: the transfer's source
  std::vector<AcceptedTransfer> transfers_in;  // accepted transfers into this pair, in order
  // Whether the agent that solved it came through a transfer: started from a pair other than its parent, took an
  // accepted transfer before or at its solve, or was solved by one.
  bool solved_through_transfer = false;
};

// From the first environment (index 0) down to pair_id's; empty for an unknown pair.
std::vector<LineageLink> lineage_chain(const RunSnapshot& run, const RunMetrics& metrics, int pair_id);

const char* to_string(SolveCause cause);

}  // namespace poet
