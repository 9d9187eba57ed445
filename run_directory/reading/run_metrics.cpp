#include "run_directory/reading/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "common/formats/envgen/env_proto.h"
#include "run_directory/reading/event_fields.h"

namespace poet {
namespace {

int level_of(const EnvVector& e) { return static_cast<int>(difficulty(e)); }
int level_of(const EnvEncoding& e) { return static_cast<int>(difficulty(e)); }

// The 5-vector of a "child" event; nullopt when the event does not carry one.
std::optional<EnvVector> child_vector(const nlohmann::json& event) {
  const auto found = event.find("e");
  if (found == event.end() || !found->is_array() || found->size() != 5) return std::nullopt;
  EnvVector v{};
  for (size_t i = 0; i < 5; ++i) {
    if (!(*found)[i].is_number()) return std::nullopt;
    v[i] = (*found)[i].get<double>();
  }
  return v;
}

LevelSolveSummary summarise(const std::vector<int>& iterations) {
  LevelSolveSummary s;
  s.count = static_cast<int>(iterations.size());
  if (iterations.empty()) return s;
  s.min = *std::min_element(iterations.begin(), iterations.end());
  s.max = *std::max_element(iterations.begin(), iterations.end());
  double sum = 0;
  for (int v : iterations) sum += v;
  s.mean = sum / s.count;
  if (s.count > 1) {
    double squares = 0;
    for (int v : iterations) squares += (v - s.mean) * (v - s.mean);
    s.sd = std::sqrt(squares / (s.count - 1));
  }
  return s;
}

std::optional<EnvEncoding> own_target(const RunState& state) {
  if (!state.settings.target) return std::nullopt;
  return state.settings.target->encoding;
}

TargetDistance closest_to(const RunState& state, const EnvEncoding& target) {
  TargetDistance out;
  out.target_name = target.name;
  out.target = env_vector(target);
  const auto consider = [&](const EnvEncoding& solved) {
    const double d = normalized_distance(env_vector(solved), out.target);
    if (!out.distance || d < *out.distance) {
      out.distance = d;
      out.closest_env = solved.name;
      out.closest = env_vector(solved);
    }
  };
  // the direct path's one pair keeps its first solve across stages while its environment moves on: there the
  // stages say which environments were solved
  if (state.settings.mode != RunMode::kDirectPath)
    for (const Pair& p : state.pairs)
      if (p.solved()) consider(p.env.encoding);
  for (const CurriculumStage& stage : state.stages)
    if (stage.solved_iteration != kNone) consider(stage.env.encoding);
  return out;
}

// The cost of the run at each iteration: the counters of its last pair_stats row, and its wall time.
class CostByIteration {
 public:
  explicit CostByIteration(const RunSnapshot& run) {
    for (const StatsRow& row : run.stats) counters_[row.iteration] = {row.run_rollouts, row.run_env_steps};
    for (const WallTime& w : run.wall_times) wall_[w.iteration] = w.seconds;
  }

  Milestone at(int iteration) const {
    Milestone m;
    m.iteration = iteration;
    if (const auto c = counters_.find(iteration); c != counters_.end()) std::tie(m.rollouts, m.env_steps) = c->second;
    // the first saved iteration at or after it: with checkpoint_interval > 1 not every iteration has a time
    if (const auto w = wall_.lower_bound(iteration); w != wall_.end()) m.wall_s = w->second;
    return m;
  }

 private:
  std::map<int, std::pair<int64_t, int64_t>> counters_;
  std::map<int, double> wall_;
};

void keep_first(std::optional<Milestone>& slot, int iteration, const CostByIteration& cost) {
  if (!slot || iteration < slot->iteration) slot = cost.at(iteration);
}

}  // namespace

std::vector<FrontierPoint> frontier_over_time(const RunState& state) {
  // each pair raises the admitted frontier at its creation and the solved one at its first solve
  std::vector<FrontierPoint> out(static_cast<size_t>(std::max(0, state.next_iteration)));
  for (size_t t = 0; t < out.size(); ++t) out[t].iteration = static_cast<int>(t);
  const auto raise = [&](ObstacleMeasures FrontierPoint::*which, int from, const EnvVector& e) {
    if (from < 0) return;
    for (size_t t = static_cast<size_t>(from); t < out.size(); ++t) raise_frontier(out[t].*which, e);
  };
  for (const Pair& p : state.pairs) {
    const EnvVector e = env_vector(p.env.encoding);
    raise(&FrontierPoint::admitted, p.created_iteration, e);
    if (p.solved()) raise(&FrontierPoint::solved, p.first_solved_iteration, e);
  }
  return out;
}

RunMetrics compute_run_metrics(const RunSnapshot& run, const std::optional<EnvEncoding>& target) {
  const RunState& state = run.state;
  RunMetrics m;
  m.iterations_done = state.next_iteration;
  const CostByIteration cost(run);

  // per-iteration increments, then accumulated
  std::vector<LevelCounts> added(static_cast<size_t>(std::max(0, m.iterations_done)));
  const auto at = [&](int iteration) -> LevelCounts* {
    if (iteration < 0 || iteration >= m.iterations_done) return nullptr;
    return &added[static_cast<size_t>(iteration)];
  };
  for (const nlohmann::json& event : run.events) {
    const int iteration = event["iteration"].get<int>();
    const std::string name = event["event"].get<std::string>();
    if (name == "child") {
      if (field_or(event, "duplicate", false)) {
        m.duplicates += 1;
        continue;
      }
      const std::optional<EnvVector> e = child_vector(event);
      LevelCounts* slot = at(iteration);
      if (!e || !slot) continue;
      const size_t level = static_cast<size_t>(level_of(*e));
      slot->created[level] += 1;
      keep_first(m.firsts[level].created, iteration, cost);
      if (field_or(event, "passed_mc", false)) slot->passed_mc[level] += 1;
    } else if (name == "transfer") {
      m.accepted_transfers.push_back({iteration, field_or(event, "target", -1), field_or(event, "source", -1),
                                      field_or(event, "proposal", false), field_or(event, "score", 0.0),
                                      field_or(event, "previous_score", 0.0)});
    }
  }
  for (const Pair& p : state.pairs) {
    const size_t level = static_cast<size_t>(level_of(p.env.encoding));
    if (LevelCounts* slot = at(p.created_iteration)) {
      slot->admitted[level] += 1;
      keep_first(m.firsts[level].admitted, p.created_iteration, cost);
    }
    if (p.solved()) {
      if (LevelCounts* slot = at(p.first_solved_iteration)) {
        slot->solved[level] += 1;
        keep_first(m.firsts[level].solved, p.first_solved_iteration, cost);
      }
      m.solve_times.push_back({p.id, static_cast<int>(level), p.created_iteration, p.first_solved_iteration});
    }
  }
  LevelCounts running;
  for (int t = 0; t < m.iterations_done; ++t) {
    const LevelCounts& add = added[static_cast<size_t>(t)];
    for (size_t l = 0; l < kLevels; ++l) {
      running.created[l] += add.created[l];
      running.passed_mc[l] += add.passed_mc[l];
      running.admitted[l] += add.admitted[l];
      running.solved[l] += add.solved[l];
    }
    m.over_time.push_back({t, running});
  }
  m.total = running;

  for (int level = 0; level < kLevels; ++level) {
    std::vector<int> iterations;
    for (const SolveTime& s : m.solve_times)
      if (s.level == level) iterations.push_back(s.solved - s.created);
    m.solve_summary[static_cast<size_t>(level)] = summarise(iterations);
  }
  m.frontier_over_time = frontier_over_time(state);
  m.phase_blocks = phase_blocks(run.wall_times, phase_block_iterations(m.iterations_done));
  m.annecs_over_time = annecs_over_time(state);
  m.annecs = annecs_at(state, m.iterations_done - 1);
  m.transfer_attempts = state.counters.transfer_attempts;
  m.transfer_successes = state.counters.transfer_successes;

  const std::optional<EnvEncoding> goal = target ? target : own_target(state);
  if (goal) m.closest_to_target = closest_to(state, *goal);
  return m;
}

std::vector<PhaseBlock> phase_blocks(const std::vector<WallTime>& times, int block_iterations) {
  std::vector<PhaseBlock> blocks;
  double before = 0;
  for (const WallTime& line : times) {
    const int first = line.iteration / block_iterations * block_iterations;
    if (blocks.empty() || blocks.back().first != first)
      blocks.push_back({.first = first, .last = first + block_iterations - 1});
    PhaseBlock& block = blocks.back();
    block.wall_s += line.seconds - before;
    if (line.waiting) {
      block.waited += 1;
      block.waiting_s += *line.waiting;
      block.waited_wall_s += line.seconds - before;
    }
    before = line.seconds;
    block.lines += 1;
    if (line.phases) {
      block.timed += 1;
      for (size_t k = 0; k < block.phases.size(); ++k) block.phases[k] += (*line.phases)[k];
    }
  }
  if (!blocks.empty()) blocks.back().last = std::min(blocks.back().last, times.back().iteration);
  return blocks;
}

int phase_block_iterations(int iterations) {
  for (int scale = 1;; scale *= 10)
    for (const int step : {1, 2, 5})
      if (int64_t{step} * scale * 10 >= iterations) return step * scale;
}

}  // namespace poet
