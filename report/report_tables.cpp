#include "report/report_tables.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <vector>

#include "common/text/text_format.h"
#include "engine/engine.h"
#include "run_directory/reading/goal_switching.h"
#include "run_directory/reading/report_json.h"

namespace poet {
namespace {

// printf's formatting appended to out, at any length: the tables keep the widths and precisions the tool always
// printed, and a long run directory is never cut short.

std::string describe_link(const LineageLink& l) {
  std::string text = "pair " + std::to_string(l.pair) + " " + l.env + " (" + level_name(static_cast<size_t>(l.level)) +
                     "), created " + std::to_string(l.created);
  if (l.first_theta_from != kNone) {
    char score[32];
    std::snprintf(score, sizeof score, "%.1f", l.admission_score);
    text += ", first θ from pair " + std::to_string(l.first_theta_from) +
            (l.first_by_proposal ? " (proposal, " : " (direct, ") + score + ")";
  }
  for (const AcceptedTransfer& t : l.transfers_in) {
    char gain[96];
    std::snprintf(gain, sizeof gain, "%+.1f (%.1f → %.1f)", t.score - t.previous_score, t.previous_score, t.score);
    text += "; transfer at " + std::to_string(t.iteration) + " from pair " + std::to_string(t.source) +
            (t.proposal ? " (proposal) " : " (direct) ") + gain;
  }
  if (l.solved == kNone) return text + "; not solved";
  text += "; solved at " + std::to_string(l.solved) + " " + to_string(l.cause);
  if (l.solved_by != kNone) text += " from pair " + std::to_string(l.solved_by);
  if (l.solved_through_transfer) text += ", by an agent that came through a transfer";
  return text;
}

void goal_switching(std::string& out, const RunSnapshot& run, const RunMetrics& m) {
  const std::vector<int> ids = lineage_pairs(run);
  if (ids.empty()) return;
  const bool beyond_easy = difficulty(run.state.find(ids[0])->env.encoding) != Difficulty::kEasy;
  append_printf(out, "Lineage of %s (first environment first; goal switching: who solved each, and the transfers taken)\n",
              beyond_easy ? "each environment solved at challenging or above" : "the deepest solved environment");
  for (int id : ids) {
    const std::vector<LineageLink> chain = lineage_chain(run, m, id);
    const auto through =
        std::count_if(chain.begin(), chain.end(), [](const LineageLink& l) { return l.solved_through_transfer; });
    append_printf(out, "  pair %d: %zu environments, %td of them solved by an agent that came through a transfer\n", id,
                chain.size(), through);
    for (const LineageLink& l : chain) append_printf(out, "    %s\n", describe_link(l).c_str());
  }
  append_printf(out, "\n");
}

void milestones(std::string& out, const RunSnapshot& run, const RunMetrics& m) {
  append_printf(out,
      "When each level was first reached (the run's rollouts and environment steps by that iteration's ES steps; "
      "wall time by the checkpoint that saved it)\n");
  append_printf(out, "  %-22s %-9s %9s %10s %11s %10s\n", "level", "first", "iteration", "rollouts", "env steps", "wall time");
  for (size_t l = 0; l < kLevels; ++l) {
    const LevelFirsts& f = m.firsts[l];
    const std::pair<const char*, const std::optional<Milestone>*> rows[] = {
        {"created", &f.created}, {"admitted", &f.admitted}, {"solved", &f.solved}};
    for (const auto& [what, slot] : rows) {
      if (!*slot) continue;
      const Milestone& ms = **slot;
      char rollouts[32] = "-", steps[32] = "-", wall[32] = "-";
      if (ms.rollouts >= 0) std::snprintf(rollouts, sizeof rollouts, "%lld", static_cast<long long>(ms.rollouts));
      if (ms.env_steps >= 0) std::snprintf(steps, sizeof steps, "%.1f M", static_cast<double>(ms.env_steps) / 1e6);
      if (ms.wall_s) {
        const long total = std::lround(*ms.wall_s);
        std::snprintf(wall, sizeof wall, "%ld:%02ld:%02ld", total / 3600, total / 60 % 60, total % 60);
      }
      append_printf(out, "  %-22s %-9s %9d %10s %11s %10s\n", level_name(l).c_str(), what, ms.iteration, rollouts, steps,
                  wall);
    }
  }
  if (run.wall_times.empty())
    append_printf(out, "  (no wall times: %s)\n", run.wall_times_problem.empty() ? "the run directory has no wall_times.csv"
                                                                          : run.wall_times_problem.c_str());
  else if (!run.wall_times_problem.empty())
    append_printf(out, "  (wall times: %s)\n", run.wall_times_problem.c_str());
  append_printf(out, "\n");
}

void phase_times(std::string& out, const RunMetrics& m) {
  if (m.phase_blocks.empty()) return;
  append_printf(out,
      "Where the time went (wall_times.csv: each block's wall time, and the share of each phase of an iteration; "
      "other is saving and logging between iterations; waiting: the share the run loop waited for rollouts, the "
      "rest being the coordinator's own serial work)\n");
  append_printf(out, "  %-13s %10s %9s %13s %9s %12s %9s %7s %8s\n", "iterations", "wall time", "per hour", "reproduction",
              "ES steps", "evaluations", "transfer", "other", "waiting");
  for (const PhaseBlock& b : m.phase_blocks) {
    char range[32], wall[32], rate[32];
    std::snprintf(range, sizeof range, "%d-%d", b.first, b.last);
    std::snprintf(wall, sizeof wall, "%.1f min", b.wall_s / 60);
    std::snprintf(rate, sizeof rate, "%.0f", b.wall_s > 0 ? b.lines / (b.wall_s / 3600) : 0.0);
    append_printf(out, "  %-13s %10s %9s", range, wall, rate);
    if (b.timed == 0 || b.wall_s <= 0) {
      append_printf(out, "   (phases not timed by the build that ran these iterations)\n");
      continue;
    }
    double phases = 0;
    for (const double s : b.phases) phases += s;
    const auto share = [&](double s) { return 100 * s / b.wall_s; };
    char waiting[32] = "       -";  // builds before waiting_s
    if (b.waited > 0 && b.waited_wall_s > 0)
      std::snprintf(waiting, sizeof waiting, "%6.0f %%", 100 * b.waiting_s / b.waited_wall_s);
    append_printf(out, " %11.0f %% %7.0f %% %10.0f %% %7.0f %% %5.0f %% %s%s\n", share(b.phases[0]), share(b.phases[1]),
                share(b.phases[2]), share(b.phases[3]), share(std::max(0.0, b.wall_s - phases)), waiting,
                b.timed < b.lines ? "  (some iterations not timed)" : "");
  }
  append_printf(out, "\n");
}

// The run: its directory, mode, progress and counters.
void run_header(std::string& out, const RunSnapshot& run, const RunMetrics& m) {
  const RunState& state = run.state;
  append_printf(out, "Run %s: %s, seed %llu, %d of %d iterations done%s\n", run.dir.c_str(),
              std::string(mode_words(state.settings.mode)).c_str(),
              static_cast<unsigned long long>(state.settings.seed), m.iterations_done, state.settings.iterations,
              run.live ? " (live: reported as of its last checkpoint)" : "");
  append_printf(out, "%lld rollouts, %.1f M environment steps", static_cast<long long>(state.counters.rollouts),
              static_cast<double>(state.counters.env_steps) / 1e6);
  if (state.settings.env_step_budget > 0)
    append_printf(out, " (budget %.1f M%s)", static_cast<double>(state.settings.env_step_budget) / 1e6,
                budget_reached(state) ? ", reached" : "");
  append_printf(out, "\n\n");
  if (const auto level = state.settings.episodes.random_courses)
    append_printf(out,
        "Domain randomisation: every rollout ran on a course drawn at the level %s, not on the pair's "
        "environment, which only names the run (its level below is that name's)\n\n",
        std::string(to_string(*level)).c_str());
}

void levels(std::string& out, const RunState& state, const RunMetrics& m) {
  append_printf(out,
                "Environments by difficulty level (the paper's Table 1; the first environment counts as admitted at "
                "iteration 0)\n");
  append_printf(out, "  %-22s %8s %10s %9s %7s   %s\n", "level", "created", "passed MC", "admitted", "solved",
              "iterations from creation to solution");
  for (size_t l = 0; l < kLevels; ++l) {
    const LevelSolveSummary& s = m.solve_summary[l];
    char solve[96] = "-";
    if (s.count > 0)
      std::snprintf(solve, sizeof solve, "%.1f ± %.1f (min %d, max %d, n %d)", s.mean, s.sd, s.min, s.max, s.count);
    append_printf(out, "  %-22s %8lld %10lld %9lld %7lld   %s\n", level_name(l).c_str(),
                static_cast<long long>(m.total.created[l]), static_cast<long long>(m.total.passed_mc[l]),
                static_cast<long long>(m.total.admitted[l]), static_cast<long long>(m.total.solved[l]), solve);
  }
  append_printf(out, "  (%lld mutation attempts, %lld of them duplicates of an archived environment)\n\n",
              static_cast<long long>(state.counters.children_tried), static_cast<long long>(m.duplicates));
  if (state.settings.poet.environments == EnvironmentKind::kCppnTerrain)
    append_printf(out,
        "  (CPPN terrain: Table 1's levels describe obstacle courses; every CPPN course counts as easy here, "
        "and ANNECS is this run's measure)\n\n");
}

void transfers(std::string& out, const RunMetrics& m) {
  append_printf(out, "Transfers: %lld replacement attempts, %lld accepted", static_cast<long long>(m.transfer_attempts),
              static_cast<long long>(m.transfer_successes));
  if (m.transfer_attempts > 0)
    append_printf(out, " (%.1f %%)",
                100.0 * static_cast<double>(m.transfer_successes) / static_cast<double>(m.transfer_attempts));
  append_printf(out, "\n");
  const AcceptedTransfer* largest = nullptr;
  for (const AcceptedTransfer& t : m.accepted_transfers)
    if (!largest || t.score - t.previous_score > largest->score - largest->previous_score) largest = &t;
  if (largest)
    append_printf(out, "  largest gain: %+.1f (pair %d from pair %d, %s, iteration %d: %.1f → %.1f)\n",
                largest->score - largest->previous_score, largest->target, largest->source,
                largest->proposal ? "proposal" : "direct", largest->iteration, largest->previous_score, largest->score);
  append_printf(out, "\n");
}

void annecs_and_frontier(std::string& out, const RunMetrics& m) {
  append_printf(out, "ANNECS at admission: %d — %s\n", m.annecs.at_admission, kAnnecsAtAdmission);
  append_printf(out, "ANNECS at archiving: %d — %s\n\n", m.annecs.at_archiving, kAnnecsAtArchiving);
  if (!m.frontier_over_time.empty()) {
    const FrontierPoint& f = m.frontier_over_time.back();
    append_printf(out,
        "Obstacle frontier (the hardest value solved; admitted in brackets; Table 1's conditions: roughness "
        "≥ 4.5, gap top ≥ 6.0, stump top ≥ 2.4)\n  roughness %.1f (%.1f), gap top %.1f (%.1f), stump top "
        "%.1f (%.1f)\n\n",
        f.solved[0], f.admitted[0], f.solved[1], f.admitted[1], f.solved[2], f.admitted[2]);
  }
}

// Coverage of the levels by what was solved, and the solved environment closest to the target.
void coverage_section(std::string& out, const RunMetrics& m, const Coverage& coverage, const std::string& samples_file) {
  append_printf(out,
      "Coverage (seed %llu, %d samples per level; sum of normalised distances to the nearest environment "
      "solved at challenging or above, lower is better)\n",
      static_cast<unsigned long long>(coverage.seed), coverage.per_level);
  if (coverage.solved.empty()) {
    append_printf(out, "  not defined: the run solved no environment at challenging or above\n");
  } else {
    for (size_t l = 0; l < 3; ++l)
      append_printf(out, "  %-22s sum %.1f (mean %.3f)\n", level_name(l + 1).c_str(), *coverage.sum[l],
                  *coverage.sum[l] / coverage.per_level);
  }
  if (!samples_file.empty()) append_printf(out, "  samples and per-sample distances: %s\n", samples_file.c_str());
  if (m.closest_to_target) {
    const TargetDistance& t = *m.closest_to_target;
    if (t.distance)
      append_printf(out, "\nClosest solved environment to the target %s: %s, normalised distance %.4f\n",
                  t.target_name.c_str(), t.closest_env.c_str(), *t.distance);
    else
      append_printf(out, "\nClosest solved environment to the target %s: none solved\n", t.target_name.c_str());
  }
}

void pairs(std::string& out, const RunState& state) {
  append_printf(out, "\nPairs\n  %4s %-28s %-12s %7s %6s %6s %7s %7s %8s %8s %8s %5s\n", "id", "environment", "level",
              "created", "parent", "from", "solved", "retired", "best", "latest", "ES steps", "xfers");
  for (const Pair& p : state.pairs) {
    const std::string level(level_label(p.env.encoding));
    append_printf(out, "  %4d %-28.28s %-12.12s %7d %6s %6s %7s %7s %8.1f %8.1f %8lld %5zu\n", p.id,
                p.env.encoding.name.c_str(), level.c_str(), p.created_iteration,
                p.parent_id == kNone ? "-" : std::to_string(p.parent_id).c_str(),
                p.initial_source_pair == kNone ? "-" : std::to_string(p.initial_source_pair).c_str(),
                p.solved() ? std::to_string(p.first_solved_iteration).c_str() : "-",
                p.active() ? "-" : std::to_string(p.retired_iteration).c_str(), p.best_score, p.latest_score,
                static_cast<long long>(p.es_steps), p.transfers.size());
  }
}

}  // namespace

std::string report_table(const RunSnapshot& run, const RunMetrics& metrics, const Coverage& coverage,
                         const std::string& samples_file) {
  std::string out;
  run_header(out, run, metrics);
  levels(out, run.state, metrics);
  milestones(out, run, metrics);
  phase_times(out, metrics);
  transfers(out, metrics);
  goal_switching(out, run, metrics);
  annecs_and_frontier(out, metrics);
  coverage_section(out, metrics, coverage, samples_file);
  pairs(out, run.state);
  return out;
}

std::string report_suite_section(const std::string& suite_name, const RunSuite& scores) {
  return "\nagents on the test suite " + suite_name + ":\n" + run_suite_table(scores);
}

std::string coverage_samples_csv(const Coverage& coverage) {
  std::string text = "level,roughness,gap_lo,gap_hi,stump_lo,stump_hi,distance\n";
  for (const CoverageSample& s : coverage.samples) {
    append_printf(text, "%s,%.17g,%.17g,%.17g,%.17g,%.17g,", level_name(static_cast<size_t>(s.level)).c_str(), s.e[0],
            s.e[1], s.e[2], s.e[3], s.e[4]);
    if (s.distance) append_printf(text, "%.17g", *s.distance);
    text += "\n";
  }
  return text;
}

int deepest_pair(const RunSnapshot& run) {
  const std::vector<int> ids = lineage_pairs(run);
  return ids.empty() ? run.state.pairs.front().id : ids.back();
}

}  // namespace poet
