#include "run_directory/reading/report_json.h"

#include <map>

#include "engine/engine.h"
#include "simulation/envgen/env_distance.h"

namespace poet {
namespace {

nlohmann::ordered_json milestone_json(const std::optional<Milestone>& m) {
  if (!m) return nullptr;
  nlohmann::ordered_json out = {{"iteration", m->iteration}};
  out["rollouts"] = m->rollouts >= 0 ? nlohmann::ordered_json(m->rollouts) : nullptr;
  out["env_steps"] = m->env_steps >= 0 ? nlohmann::ordered_json(m->env_steps) : nullptr;
  out["wall_s"] = m->wall_s ? nlohmann::ordered_json(*m->wall_s) : nullptr;
  return out;
}

nlohmann::ordered_json levels_json(const RunMetrics& m) {
  nlohmann::ordered_json levels = nlohmann::ordered_json::array();
  for (size_t l = 0; l < kLevels; ++l) {
    const LevelSolveSummary& s = m.solve_summary[l];
    levels.push_back(
        {{"level", level_name(l)},
         {"created", m.total.created[l]},
         {"passed_mc", m.total.passed_mc[l]},
         {"admitted", m.total.admitted[l]},
         {"solved", m.total.solved[l]},
         {"iterations_to_solve", {{"count", s.count}, {"mean", s.mean}, {"sd", s.sd}, {"min", s.min}, {"max", s.max}}},
         {"first_created", milestone_json(m.firsts[l].created)},
         {"first_admitted", milestone_json(m.firsts[l].admitted)},
         {"first_solved", milestone_json(m.firsts[l].solved)}});
  }
  return levels;
}

nlohmann::ordered_json over_time_json(const RunMetrics& m) {
  nlohmann::ordered_json over_time = nlohmann::ordered_json::array();
  for (const LevelTimePoint& p : m.over_time)
    over_time.push_back({{"iteration", p.iteration},
                         {"created", p.total.created},
                         {"passed_mc", p.total.passed_mc},
                         {"admitted", p.total.admitted},
                         {"solved", p.total.solved}});
  return over_time;
}

nlohmann::ordered_json solve_times_json(const RunMetrics& m) {
  nlohmann::ordered_json solves = nlohmann::ordered_json::array();
  for (const SolveTime& s : m.solve_times)
    solves.push_back({{"pair", s.pair},
                      {"level", level_name(static_cast<size_t>(s.level))},
                      {"created", s.created},
                      {"solved", s.solved},
                      {"iterations", s.solved - s.created}});
  return solves;
}

nlohmann::ordered_json transfers_json(const RunMetrics& m) {
  nlohmann::ordered_json accepted = nlohmann::ordered_json::array();
  for (const AcceptedTransfer& t : m.accepted_transfers)
    accepted.push_back({{"iteration", t.iteration},
                        {"target", t.target},
                        {"source", t.source},
                        {"proposal", t.proposal},
                        {"score", t.score},
                        {"previous_score", t.previous_score},
                        {"gain", t.score - t.previous_score}});
  return {{"replacement_attempts", m.transfer_attempts},
          {"accepted", m.transfer_successes},
          {"accepted_list", std::move(accepted)}};
}

nlohmann::ordered_json annecs_json(const RunMetrics& m) {
  nlohmann::ordered_json annecs_series = nlohmann::ordered_json::array();
  for (size_t t = 0; t < m.annecs_over_time.size(); ++t)
    annecs_series.push_back({{"iteration", t},
                             {"at_admission", m.annecs_over_time[t].at_admission},
                             {"at_archiving", m.annecs_over_time[t].at_archiving}});
  return {{"at_admission", {{"value", m.annecs.at_admission}, {"definition", kAnnecsAtAdmission}}},
          {"at_archiving", {{"value", m.annecs.at_archiving}, {"definition", kAnnecsAtArchiving}}},
          {"over_time", std::move(annecs_series)}};
}

nlohmann::ordered_json frontier_json(const RunMetrics& m) {
  nlohmann::ordered_json frontier = nlohmann::ordered_json::array();
  for (const FrontierPoint& f : m.frontier_over_time) {
    nlohmann::ordered_json point = {{"iteration", f.iteration}};
    for (size_t k = 0; k < kObstacleMeasureNames.size(); ++k) {
      point["solved"][kObstacleMeasureNames[k]] = f.solved[k];
      point["admitted"][kObstacleMeasureNames[k]] = f.admitted[k];
    }
    frontier.push_back(std::move(point));
  }
  return frontier;
}

nlohmann::ordered_json time_per_phase_json(const RunMetrics& m) {
  nlohmann::ordered_json phases = nlohmann::ordered_json::array();
  for (const PhaseBlock& b : m.phase_blocks) {
    nlohmann::ordered_json block = {{"first_iteration", b.first},
                                    {"last_iteration", b.last},
                                    {"saved_iterations", b.lines},
                                    {"timed_iterations", b.timed},
                                    {"wall_s", b.wall_s}};
    for (size_t k = 0; k < kPhaseNames.size(); ++k) block[std::string(kPhaseNames[k]) + "_s"] = b.phases[k];
    block["waiting_s"] = b.waiting_s;  // over the iterations that timed it: waited_iterations, their wall time
    block["waited_iterations"] = b.waited;
    block["waited_wall_s"] = b.waited_wall_s;
    phases.push_back(std::move(block));
  }
  return phases;
}

nlohmann::ordered_json coverage_json(const Coverage& coverage, const std::string& samples_file) {
  nlohmann::ordered_json cov = {{"seed", coverage.seed},
                                {"samples_per_level", coverage.per_level},
                                {"solved_at_challenging_or_above", coverage.solved.size()}};
  for (size_t l = 0; l < 3; ++l)
    cov["sum"][level_name(l + 1)] = coverage.sum[l] ? nlohmann::ordered_json(*coverage.sum[l]) : nullptr;
  if (!samples_file.empty()) cov["samples_file"] = samples_file;
  return cov;
}

nlohmann::ordered_json pairs_json(const RunState& state) {
  nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
  for (const Pair& p : state.pairs)
    pairs.push_back({{"id", p.id},
                     {"env", p.env.encoding.name},
                     {"vector", env_vector(p.env.encoding)},
                     {"level", level_label(p.env.encoding)},
                     {"created", p.created_iteration},
                     {"parent", p.parent_id},
                     {"first_theta_from", p.initial_source_pair},
                     {"solved", p.solved() ? nlohmann::ordered_json(p.first_solved_iteration) : nullptr},
                     {"retired", p.active() ? nullptr : nlohmann::ordered_json(p.retired_iteration)},
                     {"best_score", p.best_score},
                     {"latest_score", p.latest_score},
                     {"es_steps", p.es_steps},
                     {"transfers_in", p.transfers.size()}});
  return pairs;
}

}  // namespace

std::string level_name(size_t level) { return std::string(to_string(static_cast<Difficulty>(level))); }

// Parents precede their children in the archive, so one pass gives every pair's depth.
std::vector<int> lineage_pairs(const RunSnapshot& run) {
  std::vector<int> out;
  for (const Pair& p : run.state.pairs)
    if (p.solved() && difficulty(p.env.encoding) != Difficulty::kEasy) out.push_back(p.id);
  if (!out.empty()) return out;
  std::map<int, int> depth;
  int deepest = -1;
  for (const Pair& p : run.state.pairs) {
    const auto parent = depth.find(p.parent_id);
    depth[p.id] = parent == depth.end() ? 0 : parent->second + 1;
    if (p.solved() && depth[p.id] > deepest) {
      deepest = depth[p.id];
      out = {p.id};
    }
  }
  return out;
}

nlohmann::ordered_json goal_switching_json(const RunSnapshot& run, const RunMetrics& m) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (int id : lineage_pairs(run)) {
    nlohmann::ordered_json chain = nlohmann::ordered_json::array();
    for (const LineageLink& l : lineage_chain(run, m, id)) {
      nlohmann::ordered_json transfers = nlohmann::ordered_json::array();
      for (const AcceptedTransfer& t : l.transfers_in)
        transfers.push_back({{"iteration", t.iteration},
                             {"source", t.source},
                             {"proposal", t.proposal},
                             {"gain", t.score - t.previous_score}});
      chain.push_back(
          {{"pair", l.pair},
           {"env", l.env},
           {"level", level_name(static_cast<size_t>(l.level))},
           {"created", l.created},
           {"first_theta_from", l.first_theta_from == kNone ? nullptr : nlohmann::ordered_json(l.first_theta_from)},
           {"solved", l.solved == kNone ? nullptr : nlohmann::ordered_json(l.solved)},
           {"solved_how", to_string(l.cause)},
           {"solved_by", l.solved_by == kNone ? nullptr : nlohmann::ordered_json(l.solved_by)},
           {"solved_through_transfer", l.solved_through_transfer},
           {"transfers_in", std::move(transfers)}});
    }
    out.push_back({{"pair", id}, {"chain", std::move(chain)}});
  }
  return out;
}

nlohmann::ordered_json report_json(const RunSnapshot& run, const RunMetrics& m, const Coverage& coverage,
                                   const std::string& samples_file) {
  const RunState& state = run.state;
  nlohmann::ordered_json out;
  out["run_dir"] = run.dir.string();
  out["mode"] = mode_words(state.settings.mode);
  out["seed"] = state.settings.seed;
  out["iterations_done"] = m.iterations_done;
  out["iteration_limit"] = state.settings.iterations;
  out["finished"] = run_complete(state);  // the iteration limit, the environment-step budget or a control's end
  out["live"] = run.live;
  out["rollouts"] = state.counters.rollouts;
  out["env_steps"] = state.counters.env_steps;
  out["wall_times_problem"] = run.wall_times_problem.empty() ? nullptr : nlohmann::ordered_json(run.wall_times_problem);
  out["levels"] = levels_json(m);
  out["mutation_attempts"] = state.counters.children_tried;
  out["duplicates"] = m.duplicates;
  out["over_time"] = over_time_json(m);
  out["solve_times"] = solve_times_json(m);
  out["transfers"] = transfers_json(m);
  out["goal_switching"] = goal_switching_json(run, m);
  out["annecs"] = annecs_json(m);
  out["frontier"] = frontier_json(m);
  out["time_per_phase"] = time_per_phase_json(m);
  out["coverage"] = coverage_json(coverage, samples_file);
  if (m.closest_to_target) {
    const TargetDistance& t = *m.closest_to_target;
    out["closest_to_target"] = {{"target", t.target_name},
                                {"target_vector", t.target},
                                {"distance", t.distance ? nlohmann::ordered_json(*t.distance) : nullptr},
                                {"closest_solved", t.closest_env}};
  }
  out["pairs"] = pairs_json(state);
  return out;
}

}  // namespace poet
