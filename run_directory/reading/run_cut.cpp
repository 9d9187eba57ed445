#include "run_directory/reading/run_cut.h"

#include <algorithm>
#include <map>

namespace poet {

RunSnapshot cut_run(RunSnapshot run, int last) {
  RunState& state = run.state;
  if (last + 1 >= state.next_iteration) return run;
  state.next_iteration = last + 1;
  state.finished = false;

  // the logs
  std::erase_if(run.events, [&](const nlohmann::json& e) { return e["iteration"].get<int>() > last; });
  std::erase_if(run.stats, [&](const StatsRow& row) { return row.iteration > last; });
  std::erase_if(run.wall_times, [&](const WallTime& w) { return w.iteration > last; });

  // the pairs as they stood: created by then, their solves, retirements and transfers by then, their scores and ES
  // steps from their last statistics row
  std::erase_if(state.pairs, [&](const Pair& p) { return p.created_iteration > last; });
  state.next_pair_id = state.pairs.empty() ? 0 : state.pairs.back().id + 1;
  std::map<int, const StatsRow*> last_row;
  for (const StatsRow& row : run.stats) last_row[row.pair] = &row;
  RunCounters& c = state.counters;
  c.transfer_successes = 0;
  for (Pair& p : state.pairs) {
    if (p.first_solved_iteration > last) p.first_solved_iteration = kNone;
    if (p.retired_iteration > last) p.retired_iteration = kNone;
    std::erase_if(p.transfers, [&](const TransferRecord& t) { return t.iteration > last; });
    c.transfer_successes += static_cast<int64_t>(p.transfers.size());
    if (const auto row = last_row.find(p.id); row != last_row.end()) {
      p.es_steps = row->second->es_steps;
      p.latest_score = row->second->score;
      p.latest_finished = row->second->finished;
      p.best_score = row->second->best_score;
      if (row->second->pair_env_steps >= 0) p.es_env_steps = row->second->pair_env_steps;
    }
  }

  // the counters: the run's at its last statistics row, and those its events record
  if (!run.stats.empty() && run.stats.back().run_rollouts >= 0) {
    c.rollouts = run.stats.back().run_rollouts;
    c.env_steps = run.stats.back().run_env_steps;
  }
  c.transfer_attempts = c.children_tried = c.children_passed_mc = 0;
  for (const nlohmann::json& e : run.events) {
    const std::string name = e["event"].get<std::string>();
    if (name == "transfer_round") c.transfer_attempts += e.value("pairs", 0);
    if (name == "child") {
      c.children_tried += 1;
      c.children_passed_mc += e.value("passed_mc", false) ? 1 : 0;
    }
  }
  c.children_admitted = static_cast<int64_t>(
      std::count_if(state.pairs.begin(), state.pairs.end(), [](const Pair& p) { return p.parent_id != kNone; }));
  return run;
}

std::optional<int> last_iteration_within(const RunSnapshot& run, int64_t env_steps) {
  // every row of an iteration carries the run's counters after that iteration's evaluations
  std::optional<int> within;
  for (const StatsRow& row : run.stats) {
    if (row.run_env_steps < 0) return std::nullopt;
    if (row.run_env_steps > env_steps) break;
    within = row.iteration;
  }
  return within;
}

}  // namespace poet
