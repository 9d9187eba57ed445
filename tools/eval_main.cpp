// poet-eval: a policy evaluated over a range of terrain seeds on one or more courses, or on a named held-out test
// suite (--suite; every policy of a run directory with --run-dir). Prints, per course or per suite group, how the
// episodes went; --json writes the same with every episode in machine-readable form.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/formats/course_sweep_json.h"
#include "common/formats/envgen/env_json.h"
#include "common/formats/policy/policy_file.h"
#include "common/formats/suite_score_json.h"
#include "common/formats/suite_score_table.h"
#include "common/plumbing/text_file.h"
#include "common/program/tool_flags.h"
#include "run_directory/reading/run_snapshot.h"
#include "run_directory/reading/run_suite.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/suite/course_suite.h"

namespace {

// Writes the JSON document to path ('-': stdout); false (and a message) when it cannot.
bool write_json(const std::string& path, const nlohmann::json& doc) {
  if (path == "-") {
    std::cout << doc.dump(2) << "\n";
    return true;
  }
  if (auto err = poet::write_file_atomically(path, doc.dump(2) + "\n")) {
    std::fprintf(stderr, "poet-eval: cannot write %s: %s\n", path.c_str(), err->c_str());
    return false;
  }
  return true;
}

std::string suite_list() {
  std::string names;
  for (std::string_view n : poet::suite_names()) names += (names.empty() ? "" : ", ") + std::string(n);
  return names;
}

// poet-eval's command line.
struct Options {
  std::string policy_path, seeds = "0:49", json_path, suite_name, run_dir;
  std::vector<std::string> courses, env_paths;
  poet::WalkerFlags walker;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  bool policy_given = false, suite_given = false, run_given = false;
  std::string walker_flag;  // the first of the walker's flags given, which --run-dir refuses; empty: none
};

// Parses the command line into `o`. nullopt: go on; otherwise the exit code (as parse_command_line).
std::optional<int> parse_options(int argc, char** argv, Options& o) {
  CLI::App app{"Evaluate a policy on courses over a range of terrain seeds, or on a held-out test suite"};
  auto* policy_option = app.add_option(
      "--policy", o.policy_path, "Policy file, JSON [[p0..p2803], score] (default: none; this or --run-dir is needed)");
  auto* course_option = app.add_option(
      "--course", o.courses,
      "Named course (repeatable): flat, r1, r3, hard, hardcore-like (default: flat when no --env is given)");
  auto* env_option =
      app.add_option("--env", o.env_paths,
                     "Environment definition file (repeatable), its seed replaced by the sweep's (default: none)");
  auto* seeds_option = app.add_option("--seeds", o.seeds, "Terrain seeds FIRST:LAST, inclusive (default 0:49)");
  auto* suite_option = app.add_option("--suite", o.suite_name,
                                      "Held-out test suite instead of courses: " + suite_list() + " (default: none)")
                           ->excludes(course_option, env_option, seeds_option);
  auto* run_option = app.add_option("--run-dir", o.run_dir,
                                    "Evaluate every policy of this run directory (each pair's θ and best θ) on the "
                                    "suite, with the run's own walker (default: none)")
                         ->needs(suite_option)
                         ->excludes(policy_option);
  poet::add_walker_flags(app, o.walker);
  app.add_option("--threads", o.threads, "Worker threads (default: hardware concurrency)")->check(CLI::Range(1, 256));
  app.add_option("--json", o.json_path, "Also write the results as JSON to this file ('-' for stdout) (default: none)");
  poet::add_fingerprint_flag(app);
  if (auto code = poet::parse_command_line(app, argc, argv)) return code;
  o.policy_given = static_cast<bool>(*policy_option);
  o.suite_given = static_cast<bool>(*suite_option);
  o.run_given = static_cast<bool>(*run_option);
  for (const char* flag : {"--push-scale", "--lidar", "--max-steps"})
    if (o.walker_flag.empty() && app.count(flag) > 0) o.walker_flag = flag;
  return std::nullopt;
}

// The JSON of a policy's evaluation: the walker and the policy, to which the results are added.
nlohmann::json policy_doc(const Options& o) {
  nlohmann::json doc = {
      {"push_scale", o.walker.push_scale}, {"lidar", o.walker.lidar}, {"max_steps", o.walker.max_steps}};
  doc["policy"] = o.policy_path;
  return doc;
}

// --run-dir: every policy of the run on the suite, with the run's own walker.
int evaluate_run(const Options& o, const poet::CourseSuite& suite, FILE* table) {
  if (!o.walker_flag.empty()) {
    std::fprintf(stderr, "poet-eval: %s does not go with --run-dir, which evaluates with the run's own walker\n",
                 o.walker_flag.c_str());
    return 2;
  }
  auto run = poet::read_run_snapshot(o.run_dir);
  if (!run) {
    std::fprintf(stderr, "poet-eval: %s\n", run.error().c_str());
    return 2;
  }
  const poet::RunSuite scores = poet::evaluate_run_on_suite(run->state, suite, o.threads);
  std::fputs(poet::run_suite_table(scores).c_str(), table);
  if (!o.json_path.empty() && !write_json(o.json_path, poet::run_suite_json(scores, suite, o.run_dir, true))) return 1;
  return 0;
}

int evaluate_on_suite(const Options& o, const poet::Mlp& mlp, const poet::CourseSuite& suite, FILE* table) {
  const poet::SuiteScore score = poet::run_suite(mlp, suite, o.walker.options(), o.walker.max_steps, o.threads);
  std::fputs(poet::suite_table(score).c_str(), table);
  nlohmann::json doc = policy_doc(o);
  doc.update(poet::to_json(score, suite));
  if (!o.json_path.empty() && !write_json(o.json_path, doc)) return 1;
  return 0;
}

using Targets = std::vector<std::pair<std::string, poet::EnvEncoding>>;

// The courses --course and --env name (flat when none); nullopt, after a message, when one is unknown or unreadable.
std::optional<Targets> sweep_targets(const Options& o) {
  Targets targets;
  for (const auto& name : o.courses) {
    auto encoding = poet::named_course(name);
    if (!encoding) {
      std::fprintf(stderr, "poet-eval: unknown course '%s'\n", name.c_str());
      return std::nullopt;
    }
    targets.emplace_back(name, *encoding);
  }
  for (const auto& path : o.env_paths) {
    auto def = poet::load_env_def(path);
    if (!def) {
      std::fprintf(stderr, "poet-eval: %s\n", def.error().c_str());
      return std::nullopt;
    }
    targets.emplace_back(def->encoding.name, def->encoding);
  }
  if (targets.empty()) targets.emplace_back("flat", *poet::named_course("flat"));
  return targets;
}

// The policy on each course over the seeds: a row per course.
int sweep_courses(const Options& o, const poet::Mlp& mlp, FILE* table) {
  unsigned first = 0, last = 0;
  char tail = 0;
  if (std::sscanf(o.seeds.c_str(), "%u:%u%c", &first, &last, &tail) != 2 || last < first || last >= poet::kMaxEnvSeed) {
    std::fprintf(stderr, "poet-eval: --seeds must be FIRST:LAST with 0 <= FIRST <= LAST < 1000000\n");
    return 2;
  }
  const std::optional<Targets> targets = sweep_targets(o);
  if (!targets) return 2;

  const poet::WalkerOptions options = o.walker.options();
  std::fprintf(table, "%-16s %6s %9s %9s %9s %8s %5s %9s %10s\n", "course", "seeds", "mean", "min", "max", "finished",
               "fell", "timed_out", "mean_steps");
  nlohmann::json results = nlohmann::json::array();
  for (const auto& [label, encoding] : *targets) {
    const poet::CourseSweep s =
        poet::sweep_course(mlp, label, encoding, first, int(last - first + 1), options, o.walker.max_steps, o.threads);
    std::fprintf(table, "%-16s %6zu %9.2f %9.2f %9.2f %8d %5d %9d %10.1f\n", label.c_str(), s.episodes.size(),
                 s.mean_return(), s.min_return(), s.max_return(), s.finished(), s.fell(), s.timed_out(),
                 s.mean_steps());
    results.push_back(poet::to_json(s));
  }
  nlohmann::json doc = policy_doc(o);
  doc["courses"] = results;
  if (!o.json_path.empty() && !write_json(o.json_path, doc)) return 1;
  return 0;
}

}  // namespace

int run_tool(int argc, char** argv) {
  Options o;
  if (auto code = parse_options(argc, argv, o)) return *code;
  FILE* table = o.json_path == "-" ? stderr : stdout;

  std::optional<poet::CourseSuite> suite;
  if (o.suite_given) {
    suite = poet::named_suite(o.suite_name);
    if (!suite) {
      std::fprintf(stderr, "poet-eval: unknown suite '%s' (known: %s)\n", o.suite_name.c_str(), suite_list().c_str());
      return 2;
    }
  }
  if (o.run_given) return evaluate_run(o, *suite, table);
  if (!o.policy_given) {
    std::fprintf(stderr, "poet-eval: --policy (or --run-dir with --suite) is required\n");
    return 2;
  }
  auto policy = poet::load_policy(o.policy_path);
  if (!policy) {
    std::fprintf(stderr, "poet-eval: %s\n", policy.error().c_str());
    return 2;
  }
  const poet::Mlp mlp(policy->params);
  return suite ? evaluate_on_suite(o, mlp, *suite, table) : sweep_courses(o, mlp, table);
}

int main(int argc, char** argv) { return poet::output_checked("poet-eval", run_tool(argc, argv)); }
