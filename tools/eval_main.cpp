// poet-eval: a policy evaluated over a range of terrain seeds on one or more courses. Prints, per course, the
// mean/min/max return, how many episodes finished, fell or timed out, and the mean steps; --json writes the same
// (with every episode's return and steps) in machine-readable form.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "course_sweep_json.h"
#include "envgen/env_json.h"
#include "envgen/named_courses.h"
#include "policy/policy_file.h"
#include "text_file.h"
#include "tool_flags.h"

int main(int argc, char** argv) {
  CLI::App app{"Evaluate a policy on courses over a range of terrain seeds"};
  std::string policy_path, seeds = "0:49", json_path;
  std::vector<std::string> courses, env_paths;
  poet::WalkerFlags walker;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  app.add_option("--policy", policy_path, "Policy file, JSON [[p0..p2803], score]")->required();
  app.add_option("--course", courses, "Named course (repeatable): flat, r1, r3, hard, hardcore-like");
  app.add_option("--env", env_paths, "Environment definition file (repeatable); its seed is replaced by the sweep's");
  app.add_option("--seeds", seeds, "Terrain seeds FIRST:LAST, inclusive (default 0:49)");
  poet::add_walker_flags(app, walker);
  app.add_option("--threads", threads, "Worker threads")->check(CLI::Range(1, 256));
  app.add_option("--json", json_path, "Also write the results as JSON to this file ('-' for stdout)");
  poet::add_fingerprint_flag(app);
  if (auto code = poet::parse_command_line(app, argc, argv)) return *code;

  unsigned first = 0, last = 0;
  char tail = 0;
  if (std::sscanf(seeds.c_str(), "%u:%u%c", &first, &last, &tail) != 2 || last < first || last >= poet::kMaxEnvSeed) {
    std::fprintf(stderr, "poet-eval: --seeds must be FIRST:LAST with 0 <= FIRST <= LAST < 1000000\n");
    return 2;
  }
  auto policy = poet::load_policy(policy_path);
  if (!policy) {
    std::fprintf(stderr, "poet-eval: %s\n", policy.error().c_str());
    return 2;
  }

  std::vector<std::pair<std::string, poet::EnvEncoding>> targets;
  for (const auto& name : courses) {
    auto encoding = poet::named_course(name);
    if (!encoding) {
      std::fprintf(stderr, "poet-eval: unknown course '%s'\n", name.c_str());
      return 2;
    }
    targets.emplace_back(name, *encoding);
  }
  for (const auto& path : env_paths) {
    auto def = poet::load_env_def(path);
    if (!def) {
      std::fprintf(stderr, "poet-eval: %s\n", def.error().c_str());
      return 2;
    }
    targets.emplace_back(def->encoding.name, def->encoding);
  }
  if (targets.empty()) targets.emplace_back("flat", *poet::named_course("flat"));

  const poet::Mlp mlp(policy->params);
  const poet::WalkerOptions options = walker.options();
  const bool json_to_stdout = json_path == "-";
  FILE* table = json_to_stdout ? stderr : stdout;
  std::fprintf(table, "%-16s %6s %9s %9s %9s %8s %5s %9s %10s\n", "course", "seeds", "mean", "min", "max", "finished",
               "fell", "timed_out", "mean_steps");
  nlohmann::json results = nlohmann::json::array();
  for (const auto& [label, encoding] : targets) {
    const poet::CourseSweep s =
        poet::sweep_course(mlp, label, encoding, first, int(last - first + 1), options, walker.max_steps, threads);
    std::fprintf(table, "%-16s %6zu %9.2f %9.2f %9.2f %8d %5d %9d %10.1f\n", label.c_str(), s.episodes.size(),
                 s.mean_return(), s.min_return(), s.max_return(), s.finished(), s.fell(), s.timed_out(),
                 s.mean_steps());
    results.push_back(poet::to_json(s));
  }

  if (!json_path.empty()) {
    const nlohmann::json doc = {{"policy", policy_path},
                                {"push_scale", walker.push_scale},
                                {"lidar", walker.lidar},
                                {"max_steps", walker.max_steps},
                                {"courses", results}};
    if (json_to_stdout) {
      std::cout << doc.dump(2) << "\n";
    } else if (auto err = poet::write_file_atomically(json_path, doc.dump(2) + "\n")) {
      std::fprintf(stderr, "poet-eval: cannot write %s: %s\n", json_path.c_str(), err->c_str());
      return 1;
    }
  }
  return 0;
}
