// poet-report: the paper's metrics of a run directory (spec §3) as a table, JSON and PNG plots. Reads a
// finished, live or resumed run and never changes it: it reads the last checkpoint and the log lines that
// checkpoint has seen, so a run being written is reported as of its last checkpoint.
//   poet-report --run-dir DIR [--json FILE|-] [--plots DIR] [--target ENV.json] [--coverage-samples FILE]
//               [--until-iteration T | --until-env-steps N]   the run as it stood then
//               (run_directory/reading/run_cut.h)
//               [--suite NAME [--threads N]]   every agent of the run on a held-out test suite
//               (run_directory/reading/run_suite.h)

#include <CLI/CLI.hpp>
#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "common/formats/envgen/env_json.h"
#include "common/plumbing/text_file.h"
#include "common/program/tool_flags.h"
#include "pictures/canvas.h"
#include "report/report_plot_files.h"
#include "report/report_tables.h"
#include "run_directory/reading/coverage.h"
#include "run_directory/reading/report_json.h"
#include "run_directory/reading/run_cut.h"
#include "run_directory/reading/run_metrics.h"
#include "run_directory/reading/run_snapshot.h"
#include "run_directory/reading/run_suite.h"
#include "simulation/suite/course_suite.h"

namespace poet {
namespace {
namespace fs = std::filesystem;

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
                 "Write the metrics as JSON to this file ('-' for stdout, instead of the table) (default: none)");
  app.add_option(
      "--plots", o.plots_dir,
      "Write scores.png, levels.png, annecs.png, frontier.png, phases.png, tree.png and lineage.png (the courses along "
      "the last lineage the table shows) into this directory (default: none)");
  app.add_option("--target", o.target_path,
                 "Environment file (envs/*.env.json form): report the solved environment closest to it (default: a "
                 "control run's own target)");
  app.add_option("--coverage-samples", o.samples_path,
                 "Write the coverage sample and per-sample distances (CSV) here (default: none)");
  app.add_option("--coverage-seed", o.coverage_seed, "Seed of the coverage sample")->capture_default_str();
  app.add_option("--coverage-per-level", o.per_level, "Coverage samples per difficulty level (paper: 1000)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  auto* until_option = app.add_option("--until-iteration", o.until_iteration,
                                      "Report the run as it stood at the end of this iteration (to compare runs at "
                                      "equal budgets; default: the last)")
                           ->check(CLI::Range(0, INT_MAX));
  app.add_option("--until-env-steps", o.until_env_steps,
                 "Report the run as it stood at the last iteration within this many environment steps (counted by "
                 "that iteration's ES steps and evaluations; default: no limit)")
      ->check(CLI::Range(int64_t{0}, INT64_MAX))
      ->excludes(until_option);
  auto* suite_option =
      app.add_option(
             "--suite", o.suite_name,
             "Also run every agent of the run (each pair's θ and its best θ) on this held-out test suite and report "
             "the best single agent and the best per group, as poet-eval --run-dir does (default: none)")
          // a cut run keeps today's θs (run_directory/reading/run_cut.h): its agents are not the ones it had then
          ->excludes(until_option, app.get_option("--until-env-steps"));
  app.add_option("--threads", o.threads, "Threads for --suite's episodes (default: hardware concurrency)")
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
  for (const PlotFile& plot : report_plot_files(run, metrics)) {
    const std::string path = (fs::path(plots_dir) / plot.name).string();
    const std::string error =
        plot.bytes ? write_bytes(path, *plot.bytes) : "cannot draw " + path + ": " + plot.bytes.error();
    if (!error.empty()) return error;
  }
  return "";
}

// Writes the coverage sample as CSV; returns what went wrong, or "".
std::string write_samples(const std::string& path, const Coverage& coverage) {
  const auto error = write_file_atomically(path, coverage_samples_csv(coverage));
  return error ? "cannot write " + path + ": " + *error : "";
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
    std::string text = report_table(run, metrics, coverage, o.samples_path);
    if (suite_scores) text += report_suite_section(in->suite->name, *suite_scores);
    std::fputs(text.c_str(), stdout);
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
