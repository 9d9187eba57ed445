// poet-report: the paper's metrics of a run directory (spec §3) as a table, JSON and PNG plots. Reads a
// finished, live or resumed run and never changes it: it reads the last checkpoint and the log lines that
// checkpoint has seen, so a run being written is reported as of its last checkpoint.
//   poet-report --run-dir DIR [--json FILE|-] [--plots DIR] [--target ENV.json] [--coverage-samples FILE]
//               [--until-iteration T | --until-env-steps N]   the run as it stood then
//               (run_directory/reading/run_cut.h)
//               [--suite NAME [--threads N]]   every agent of the run on a held-out test suite
//               (run_directory/reading/run_suite.h)

#include <CLI/CLI.hpp>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "common/envgen/env_json.h"
#include "common/text_file.h"
#include "common/tool_flags.h"
#include "engine/engine.h"
#include "report/report_plots.h"
#include "report/run_pictures.h"
#include "run_directory/reading/coverage.h"
#include "run_directory/reading/goal_switching.h"
#include "run_directory/reading/report_json.h"
#include "run_directory/reading/run_cut.h"
#include "run_directory/reading/run_metrics.h"
#include "run_directory/reading/run_snapshot.h"
#include "run_directory/reading/run_suite.h"
#include "simulation/suite/course_suite.h"

namespace poet {
namespace {
namespace fs = std::filesystem;

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

void print_goal_switching(const RunSnapshot& run, const RunMetrics& m) {
  const std::vector<int> ids = lineage_pairs(run);
  if (ids.empty()) return;
  const bool beyond_easy = difficulty(run.state.find(ids[0])->env.encoding) != Difficulty::kEasy;
  std::printf("Lineage of %s (first environment first; goal switching: who solved each, and the transfers taken)\n",
              beyond_easy ? "each environment solved at challenging or above" : "the deepest solved environment");
  for (int id : ids) {
    const std::vector<LineageLink> chain = lineage_chain(run, m, id);
    const auto through =
        std::count_if(chain.begin(), chain.end(), [](const LineageLink& l) { return l.solved_through_transfer; });
    std::printf("  pair %d: %zu environments, %td of them solved by an agent that came through a transfer\n", id,
                chain.size(), through);
    for (const LineageLink& l : chain) std::printf("    %s\n", describe_link(l).c_str());
  }
  std::printf("\n");
}

void print_milestones(const RunSnapshot& run, const RunMetrics& m) {
  std::printf(
      "When each level was first reached (the run's rollouts and environment steps by that iteration's ES steps; "
      "wall time by the checkpoint that saved it)\n");
  std::printf("  %-22s %-9s %9s %10s %11s %10s\n", "level", "first", "iteration", "rollouts", "env steps", "wall time");
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
      std::printf("  %-22s %-9s %9d %10s %11s %10s\n", level_name(l).c_str(), what, ms.iteration, rollouts, steps,
                  wall);
    }
  }
  if (run.wall_times.empty())
    std::printf("  (no wall times: %s)\n", run.wall_times_problem.empty() ? "the run directory has no wall_times.csv"
                                                                          : run.wall_times_problem.c_str());
  else if (!run.wall_times_problem.empty())
    std::printf("  (wall times: %s)\n", run.wall_times_problem.c_str());
  std::printf("\n");
}

void print_phase_times(const RunMetrics& m) {
  if (m.phase_blocks.empty()) return;
  std::printf(
      "Where the time went (wall_times.csv: each block's wall time, and the share of each phase of an iteration; "
      "other is saving and logging between iterations; waiting: the share the run loop waited for rollouts, the "
      "rest being the coordinator's own serial work)\n");
  std::printf("  %-13s %10s %9s %13s %9s %12s %9s %7s %8s\n", "iterations", "wall time", "per hour", "reproduction",
              "ES steps", "evaluations", "transfer", "other", "waiting");
  for (const PhaseBlock& b : m.phase_blocks) {
    char range[32], wall[32], rate[32];
    std::snprintf(range, sizeof range, "%d-%d", b.first, b.last);
    std::snprintf(wall, sizeof wall, "%.1f min", b.wall_s / 60);
    std::snprintf(rate, sizeof rate, "%.0f", b.wall_s > 0 ? b.lines / (b.wall_s / 3600) : 0.0);
    std::printf("  %-13s %10s %9s", range, wall, rate);
    if (b.timed == 0 || b.wall_s <= 0) {
      std::printf("   (phases not timed by the build that ran these iterations)\n");
      continue;
    }
    double phases = 0;
    for (const double s : b.phases) phases += s;
    const auto share = [&](double s) { return 100 * s / b.wall_s; };
    char waiting[32] = "       -";  // builds before waiting_s
    if (b.waited > 0 && b.waited_wall_s > 0)
      std::snprintf(waiting, sizeof waiting, "%6.0f %%", 100 * b.waiting_s / b.waited_wall_s);
    std::printf(" %11.0f %% %7.0f %% %10.0f %% %7.0f %% %5.0f %% %s%s\n", share(b.phases[0]), share(b.phases[1]),
                share(b.phases[2]), share(b.phases[3]), share(std::max(0.0, b.wall_s - phases)), waiting,
                b.timed < b.lines ? "  (some iterations not timed)" : "");
  }
  std::printf("\n");
}

// The run: its directory, mode, progress and counters.
void print_run_header(const RunSnapshot& run, const RunMetrics& m) {
  const RunState& state = run.state;
  std::printf("Run %s: %s, seed %llu, %d of %d iterations done%s\n", run.dir.c_str(),
              std::string(mode_words(state.settings.mode)).c_str(),
              static_cast<unsigned long long>(state.settings.seed), m.iterations_done, state.settings.iterations,
              run.live ? " (live: reported as of its last checkpoint)" : "");
  std::printf("%lld rollouts, %.1f M environment steps", static_cast<long long>(state.counters.rollouts),
              static_cast<double>(state.counters.env_steps) / 1e6);
  if (state.settings.env_step_budget > 0)
    std::printf(" (budget %.1f M%s)", static_cast<double>(state.settings.env_step_budget) / 1e6,
                budget_reached(state) ? ", reached" : "");
  std::printf("\n\n");
  if (const auto level = state.settings.episodes.random_courses)
    std::printf(
        "Domain randomisation: every rollout ran on a course drawn at the level %s, not on the pair's "
        "environment, which only names the run (its level below is that name's)\n\n",
        std::string(to_string(*level)).c_str());
}

void print_levels(const RunState& state, const RunMetrics& m) {
  std::printf(
      "Environments by difficulty level (spec §1.4; the first environment counts as admitted at iteration 0)\n");
  std::printf("  %-22s %8s %10s %9s %7s   %s\n", "level", "created", "passed MC", "admitted", "solved",
              "iterations from creation to solution");
  for (size_t l = 0; l < kLevels; ++l) {
    const LevelSolveSummary& s = m.solve_summary[l];
    char solve[96] = "-";
    if (s.count > 0)
      std::snprintf(solve, sizeof solve, "%.1f ± %.1f (min %d, max %d, n %d)", s.mean, s.sd, s.min, s.max, s.count);
    std::printf("  %-22s %8lld %10lld %9lld %7lld   %s\n", level_name(l).c_str(),
                static_cast<long long>(m.total.created[l]), static_cast<long long>(m.total.passed_mc[l]),
                static_cast<long long>(m.total.admitted[l]), static_cast<long long>(m.total.solved[l]), solve);
  }
  std::printf("  (%lld mutation attempts, %lld of them duplicates of an archived environment)\n\n",
              static_cast<long long>(state.counters.children_tried), static_cast<long long>(m.duplicates));
  if (state.settings.poet.environments == EnvironmentKind::kCppnTerrain)
    std::printf(
        "  (CPPN terrain: Table 1's levels describe obstacle courses; every CPPN course counts as easy here, "
        "and ANNECS is this run's measure)\n\n");
}

void print_transfers(const RunMetrics& m) {
  std::printf("Transfers: %lld replacement attempts, %lld accepted", static_cast<long long>(m.transfer_attempts),
              static_cast<long long>(m.transfer_successes));
  if (m.transfer_attempts > 0)
    std::printf(" (%.1f %%)",
                100.0 * static_cast<double>(m.transfer_successes) / static_cast<double>(m.transfer_attempts));
  std::printf("\n");
  const AcceptedTransfer* largest = nullptr;
  for (const AcceptedTransfer& t : m.accepted_transfers)
    if (!largest || t.score - t.previous_score > largest->score - largest->previous_score) largest = &t;
  if (largest)
    std::printf("  largest gain: %+.1f (pair %d from pair %d, %s, iteration %d: %.1f → %.1f)\n",
                largest->score - largest->previous_score, largest->target, largest->source,
                largest->proposal ? "proposal" : "direct", largest->iteration, largest->previous_score, largest->score);
  std::printf("\n");
}

void print_annecs_and_frontier(const RunMetrics& m) {
  std::printf("ANNECS at admission: %d — %s\n", m.annecs.at_admission, kAnnecsAtAdmission);
  std::printf("ANNECS at archiving: %d — %s\n\n", m.annecs.at_archiving, kAnnecsAtArchiving);
  if (!m.frontier_over_time.empty()) {
    const FrontierPoint& f = m.frontier_over_time.back();
    std::printf(
        "Obstacle frontier (the hardest value solved; admitted in brackets; Table 1's conditions: roughness "
        "≥ 4.5, gap top ≥ 6.0, stump top ≥ 2.4)\n  roughness %.1f (%.1f), gap top %.1f (%.1f), stump top "
        "%.1f (%.1f)\n\n",
        f.solved[0], f.admitted[0], f.solved[1], f.admitted[1], f.solved[2], f.admitted[2]);
  }
}

// Coverage of the levels by what was solved, and the solved environment closest to the target.
void print_coverage(const RunMetrics& m, const Coverage& coverage, const std::string& samples_file) {
  std::printf(
      "Coverage (seed %llu, %d samples per level; sum of normalised distances to the nearest environment "
      "solved at challenging or above, lower is better)\n",
      static_cast<unsigned long long>(coverage.seed), coverage.per_level);
  if (coverage.solved.empty()) {
    std::printf("  not defined: the run solved no environment at challenging or above\n");
  } else {
    for (size_t l = 0; l < 3; ++l)
      std::printf("  %-22s sum %.1f (mean %.3f)\n", level_name(l + 1).c_str(), *coverage.sum[l],
                  *coverage.sum[l] / coverage.per_level);
  }
  if (!samples_file.empty()) std::printf("  samples and per-sample distances: %s\n", samples_file.c_str());
  if (m.closest_to_target) {
    const TargetDistance& t = *m.closest_to_target;
    if (t.distance)
      std::printf("\nClosest solved environment to the target %s: %s, normalised distance %.4f\n",
                  t.target_name.c_str(), t.closest_env.c_str(), *t.distance);
    else
      std::printf("\nClosest solved environment to the target %s: none solved\n", t.target_name.c_str());
  }
}

void print_pairs(const RunState& state) {
  std::printf("\nPairs\n  %4s %-28s %-12s %7s %6s %6s %7s %7s %8s %8s %8s %5s\n", "id", "environment", "level",
              "created", "parent", "from", "solved", "retired", "best", "latest", "ES steps", "xfers");
  for (const Pair& p : state.pairs) {
    const std::string level(level_label(p.env.encoding));
    std::printf("  %4d %-28.28s %-12.12s %7d %6s %6s %7s %7s %8.1f %8.1f %8lld %5zu\n", p.id,
                p.env.encoding.name.c_str(), level.c_str(), p.created_iteration,
                p.parent_id == kNone ? "-" : std::to_string(p.parent_id).c_str(),
                p.initial_source_pair == kNone ? "-" : std::to_string(p.initial_source_pair).c_str(),
                p.solved() ? std::to_string(p.first_solved_iteration).c_str() : "-",
                p.active() ? "-" : std::to_string(p.retired_iteration).c_str(), p.best_score, p.latest_score,
                static_cast<long long>(p.es_steps), p.transfers.size());
  }
}

void print_table(const RunSnapshot& run, const RunMetrics& m, const Coverage& coverage,
                 const std::string& samples_file) {
  print_run_header(run, m);
  print_levels(run.state, m);
  print_milestones(run, m);
  print_phase_times(m);
  print_transfers(m);
  print_goal_switching(run, m);
  print_annecs_and_frontier(m);
  print_coverage(m, coverage, samples_file);
  print_pairs(run.state);
}

// The pair whose lineage the plots draw: the last that print_goal_switching shows (the first pair when none).
int deepest_pair(const RunSnapshot& run) {
  const std::vector<int> ids = lineage_pairs(run);
  return ids.empty() ? run.state.pairs.front().id : ids.back();
}

std::string write_samples(const std::string& path, const Coverage& coverage) {
  std::string text = "level,roughness,gap_lo,gap_hi,stump_lo,stump_hi,distance\n";
  char line[256];
  for (const CoverageSample& s : coverage.samples) {
    std::snprintf(line, sizeof line, "%s,%.17g,%.17g,%.17g,%.17g,%.17g,",
                  level_name(static_cast<size_t>(s.level)).c_str(), s.e[0], s.e[1], s.e[2], s.e[3], s.e[4]);
    text += line;
    if (s.distance) {
      std::snprintf(line, sizeof line, "%.17g", *s.distance);
      text += line;
    }
    text += "\n";
  }
  const auto error = write_file_atomically(path, text);
  return error ? "cannot write " + path + ": " + *error : "";
}

// poet-report's command line.
struct Options {
  std::string run_dir, json_path, plots_dir, target_path, samples_path;
  uint64_t coverage_seed = kDefaultCoverageSeed;
  int per_level = kDefaultCoveragePerLevel;
  int until_iteration = 0;
  int64_t until_env_steps = 0;
  bool until_iteration_given = false;
  bool until_env_steps_given = false;
  std::string suite_name;
  bool suite_given = false;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
};

// Parses the command line into `o`. nullopt: go on; otherwise the exit code (as parse_command_line).
std::optional<int> parse_options(int argc, char** argv, Options& o) {
  CLI::App app{"The paper's metrics of a run directory: a table, JSON and plots. Never changes the run."};
  app.add_option("--run-dir", o.run_dir, "Run directory (finished, live or resumed)")->required();
  app.add_option("--json", o.json_path,
                 "Write the metrics as JSON to this file ('-' for stdout, instead of the table)");
  app.add_option(
      "--plots", o.plots_dir,
      "Write scores.png, levels.png, annecs.png, frontier.png, phases.png, tree.png and lineage.png (the courses along "
      "the last lineage the table shows) into this directory");
  app.add_option("--target", o.target_path,
                 "Environment file (envs/*.env.json form): report the solved environment closest to it (default: a "
                 "control run's own target)");
  app.add_option("--coverage-samples", o.samples_path, "Write the coverage sample and per-sample distances (CSV) here");
  app.add_option("--coverage-seed", o.coverage_seed, "Seed of the coverage sample");
  app.add_option("--coverage-per-level", o.per_level, "Coverage samples per difficulty level (paper: 1000)")
      ->check(CLI::Range(1, 1000000));
  auto* until_option = app.add_option("--until-iteration", o.until_iteration,
                                      "Report the run as it stood at the end of this iteration (to compare runs at "
                                      "equal budgets)")
                           ->check(CLI::Range(0, INT_MAX));
  app.add_option("--until-env-steps", o.until_env_steps,
                 "Report the run as it stood at the last iteration within this many environment steps (counted by "
                 "that iteration's ES steps and evaluations)")
      ->check(CLI::Range(int64_t{0}, INT64_MAX))
      ->excludes(until_option);
  auto* suite_option =
      app.add_option(
             "--suite", o.suite_name,
             "Also run every agent of the run (each pair's θ and its best θ) on this held-out test suite and report "
             "the best single agent and the best per group (as poet-eval --run-dir does)")
          // a cut run keeps today's θs (run_directory/reading/run_cut.h): its agents are not the ones it had then
          ->excludes(until_option, app.get_option("--until-env-steps"));
  app.add_option("--threads", o.threads, "Threads for --suite's episodes")
      ->check(CLI::Range(1, 256))
      ->needs(suite_option);
  add_fingerprint_flag(app);
  if (auto code = parse_command_line(app, argc, argv)) return code;
  o.until_iteration_given = app.count("--until-iteration") > 0;
  o.until_env_steps_given = app.count("--until-env-steps") > 0;
  o.suite_given = static_cast<bool>(*suite_option);
  return std::nullopt;
}

// What the report is of, as the command line names it.
struct Inputs {
  std::optional<CourseSuite> suite;
  std::optional<EnvEncoding> target;
  RunSnapshot run;  // cut where --until-iteration or --until-env-steps says
};

// The inputs, or what is wrong with the command line (its outputs inside the run directory, an unknown suite,
// an unreadable target or run, a cut before the first iteration).
Expected<Inputs> read_inputs(const Options& o) {
  for (const std::string* out : {&o.json_path, &o.plots_dir, &o.samples_path})
    if (!out->empty() && *out != "-" && is_inside(*out, o.run_dir))
      return Unexpected{*out + " is inside the run directory " + o.run_dir + "; the report never writes there"};
  Inputs in;
  if (o.suite_given && !(in.suite = named_suite(o.suite_name)))
    return Unexpected{"unknown suite '" + o.suite_name + "'"};
  if (!o.target_path.empty()) {
    Expected<EnvDef> def = load_env_def(o.target_path);
    if (!def) return Unexpected{"--target: " + def.error()};
    in.target = def->encoding;
  }
  Expected<RunSnapshot> run = read_run_snapshot(o.run_dir);
  if (!run) return Unexpected{run.error()};
  in.run = std::move(*run);
  if (o.until_iteration_given || o.until_env_steps_given) {
    int until_iteration = o.until_iteration;
    if (o.until_env_steps_given) {
      const std::optional<int> last = last_iteration_within(in.run, o.until_env_steps);
      if (!last)
        return Unexpected{"--until-env-steps " + std::to_string(o.until_env_steps) + ": " +
                          (in.run.stats.empty() || in.run.stats.front().run_env_steps >= 0
                               ? "the run's first iteration took more"
                               : "this run's pair_stats.csv does not record its environment steps")};
      until_iteration = *last;
    }
    until_iteration = std::min(until_iteration, in.run.state.next_iteration - 1);
    in.run = cut_run(std::move(in.run), until_iteration);
    if (o.json_path.empty())
      std::printf("(cut at the end of iteration %d: %lld environment steps by its ES steps and evaluations)\n",
                  until_iteration, static_cast<long long>(in.run.state.counters.env_steps));
  }
  return in;
}

// Writes the plots into plots_dir; returns what went wrong, or "".
std::string write_plots(const std::string& plots_dir, const RunSnapshot& run, const RunMetrics& metrics) {
  std::error_code ec;
  fs::create_directories(plots_dir, ec);
  if (ec) return "--plots: cannot make " + plots_dir + ": " + ec.message();
  const fs::path dir(plots_dir);
  const std::pair<const char*, Expected<std::string>> plots[] = {
      {"scores.png", render_score_plot(PictureFormat::kPng, run)},
      {"levels.png", render_level_plot(PictureFormat::kPng, metrics)},
      {"annecs.png", render_annecs_plot(PictureFormat::kPng, metrics)},
      {"frontier.png", render_frontier_plot(PictureFormat::kPng, metrics)},
      {"phases.png", render_phase_plot(PictureFormat::kPng, metrics)},
      {"tree.png", render_tree_plot(PictureFormat::kPng, run, metrics)},
      {"lineage.png", render_run_picture(run, {PictureKind::kLineage, PictureEncoding::kPng, deepest_pair(run)})}};
  for (const auto& [name, bytes] : plots) {
    const std::string path = (dir / name).string();
    const std::string error = bytes ? write_bytes(path, *bytes) : "cannot draw " + path + ": " + bytes.error();
    if (!error.empty()) return error;
  }
  return "";
}

int fail(const std::string& message, int code) {
  std::cerr << "poet-report: " << message << "\n";
  return code;
}

}  // namespace
}  // namespace poet

int run_tool(int argc, char** argv) {
  using namespace poet;
  Options o;
  if (auto code = parse_options(argc, argv, o)) return *code;
  Expected<Inputs> in = read_inputs(o);
  if (!in) return fail(in.error(), 2);
  const RunSnapshot& run = in->run;
  const RunMetrics metrics = compute_run_metrics(run, in->target);
  const Coverage coverage = compute_coverage(run.state, o.coverage_seed, o.per_level);
  std::optional<RunSuite> suite_scores;
  if (in->suite) suite_scores = evaluate_run_on_suite(run.state, *in->suite, o.threads);
  auto print_all = [&] {
    print_table(run, metrics, coverage, o.samples_path);
    if (suite_scores)
      std::printf("\nagents on the test suite %s:\n%s", in->suite->name.c_str(),
                  run_suite_table(*suite_scores).c_str());
  };

  if (!o.plots_dir.empty())
    if (std::string error = write_plots(o.plots_dir, run, metrics); !error.empty()) return fail(error, 1);
  if (!o.samples_path.empty())
    if (std::string error = write_samples(o.samples_path, coverage); !error.empty()) return fail(error, 1);
  if (o.json_path.empty()) {
    print_all();
    return 0;
  }
  nlohmann::ordered_json doc = report_json(run, metrics, coverage, o.samples_path);
  if (suite_scores) doc["suite"] = run_suite_json(*suite_scores, *in->suite, o.run_dir, false);
  const std::string text = doc.dump(2) + "\n";
  if (o.json_path == "-") {
    std::cout << text;
    return 0;
  }
  if (const auto error = write_file_atomically(o.json_path, text))
    return fail("cannot write " + o.json_path + ": " + *error, 1);
  print_all();
  return 0;
}

int main(int argc, char** argv) { return poet::output_checked("poet-report", run_tool(argc, argv)); }
