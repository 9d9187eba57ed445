// poet-controls: the paper's Figure 3 at small scale for one environment a POET run solved — the control runs made
// for it (experiments/figure3.sh: the direct path and ES alone, each from the walker, several seeds) beside POET's
// lineage: ES steps, environment steps, the best score on the target, whether and when it was solved, and the
// control's closest-to-target solved environment with its normalised distance (§1.4; 0 is the target itself).
// With --rose, the picture: POET's environment in red, each control's closest solved environment in blue.
//   poet-controls --run-dir RUN --pair ID CONTROL_DIR... [--rose FILE.png|.svg] [--json FILE|-]
// Reads the run directories only. Exit codes: 0 done, 1 a file could not be written, 2 bad arguments or runs.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/plumbing/text_file.h"
#include "common/program/tool_flags.h"
#include "engine/lineage.h"
#include "report/report_plots.h"
#include "run_directory/reading/run_metrics.h"
#include "run_directory/reading/run_snapshot.h"
#include "simulation/envgen/env_distance.h"
#include "simulation/envgen/env_encoding.h"

namespace poet {
namespace {

struct ControlRow {
  std::string dir;
  std::string mode;  // "direct path" or "ES alone"
  uint64_t seed = 0;
  int64_t es_steps = 0;
  int64_t env_steps = 0;
  std::optional<double> best_on_target;  // nothing: the direct path never reached the target's stage
  std::optional<int> solved_at_es_step;  // 1-based
  TargetDistance closest;
};

bool same_environment(const EnvEncoding& a, const EnvEncoding& b) {
  return a.name == b.name && env_vector(a) == env_vector(b);
}

Expected<ControlRow> control_row(const std::string& dir, const EnvEncoding& target) {
  Expected<RunSnapshot> run = read_run_snapshot(dir);
  if (!run) return Unexpected{run.error()};
  const RunState& s = run->state;
  if (s.settings.mode != RunMode::kDirectPath && s.settings.mode != RunMode::kEsAlone)
    return Unexpected{dir + ": not a control run (direct path or ES alone)"};
  if (!s.settings.target || !same_environment(s.settings.target->encoding, target))
    return Unexpected{dir + ": its target is not the pair's environment " + target.name};
  ControlRow row;
  row.dir = dir;
  row.seed = run->config.seed();
  const Pair& pair = s.pairs.at(0);
  row.es_steps = pair.es_steps;
  row.env_steps = s.counters.env_steps;
  row.closest = compute_run_metrics(*run, target).closest_to_target.value_or(TargetDistance{});
  if (s.settings.mode == RunMode::kEsAlone) {
    row.mode = "ES alone";
    row.best_on_target = pair.best_score;
    if (pair.solved()) row.solved_at_es_step = pair.first_solved_iteration + 1;
    return row;
  }
  row.mode = "direct path";
  // the scores on the target are those of the iterations from the target's stage on
  std::optional<int> on_target_from;
  for (const CurriculumStage& stage : s.stages)
    if (same_environment(stage.env.encoding, target)) {
      on_target_from = stage.started_iteration;
      if (stage.solved_iteration != kNone) row.solved_at_es_step = stage.solved_iteration + 1;
      break;
    }
  if (on_target_from)
    for (const StatsRow& stats : run->stats)
      if (stats.iteration >= *on_target_from && (!row.best_on_target || stats.score > *row.best_on_target))
        row.best_on_target = stats.score;
  return row;
}

std::string number(std::optional<double> v, const char* format) {
  if (!v) return "-";
  char text[32];
  std::snprintf(text, sizeof text, format, *v);
  return text;
}

nlohmann::ordered_json json_of(const ControlRow& r) {
  nlohmann::ordered_json out;
  out["dir"] = r.dir;
  out["mode"] = r.mode;
  out["seed"] = r.seed;
  out["es_steps"] = r.es_steps;
  out["env_steps"] = r.env_steps;
  out["best_on_target"] = r.best_on_target ? nlohmann::ordered_json(*r.best_on_target) : nullptr;
  out["solved_at_es_step"] = r.solved_at_es_step ? nlohmann::ordered_json(*r.solved_at_es_step) : nullptr;
  out["closest_solved"] = r.closest.distance ? nlohmann::ordered_json(r.closest.closest_env) : nullptr;
  out["normalized_distance"] = r.closest.distance ? nlohmann::ordered_json(*r.closest.distance) : nullptr;
  return out;
}

// poet-controls' command line.
struct Options {
  std::string run_dir, rose_path, json_path;
  int pair_id = 0;
  std::vector<std::string> controls;
};

// Parses the command line into `o`. nullopt: go on; otherwise the exit code (as parse_command_line).
std::optional<int> parse_options(int argc, char** argv, Options& o) {
  CLI::App app{"Figure 3 at small scale: control runs for an environment POET solved, beside POET's lineage"};
  app.add_option("--run-dir", o.run_dir, "The POET run")->required();
  app.add_option("--pair", o.pair_id, "The pair whose environment the controls target")->required();
  app.add_option("controls", o.controls, "The control runs' directories (made from poet-lineage's configs)")
      ->required();
  app.add_option("--rose", o.rose_path, "Draw the rose picture here (.png or .svg) (default: none)");
  app.add_option("--json", o.json_path,
                 "Write the table as JSON here ('-' for stdout, instead of the table) (default: none)");
  add_fingerprint_flag(app);
  return parse_command_line(app, argc, argv);
}

// The rose picture's format, from its file's extension (PNG when there is no picture).
Expected<PictureFormat> rose_format(const std::string& rose_path) {
  if (rose_path.empty()) return PictureFormat::kPng;
  const std::string ext = std::filesystem::path(rose_path).extension().string();
  if (ext != ".png" && ext != ".svg") return Unexpected{"--rose " + rose_path + ": the file must end in .png or .svg"};
  return ext == ".svg" ? PictureFormat::kSvg : PictureFormat::kPng;
}

Expected<std::vector<ControlRow>> control_rows(const std::vector<std::string>& controls, const EnvEncoding& target) {
  std::vector<ControlRow> rows;
  for (const std::string& dir : controls) {
    Expected<ControlRow> row = control_row(dir, target);
    if (!row) return Unexpected{row.error()};
    rows.push_back(std::move(*row));
  }
  return rows;
}

// POET's side of the comparison: the pair, and the cost of its lineage.
struct PoetLineage {
  const Pair& pair;
  int64_t es_steps = 0;
  std::optional<int64_t> env_steps;  // nothing: not recorded
};

// Draws the rose picture into path; returns what went wrong, or "".
std::string write_rose(const std::string& path, PictureFormat format, const PoetLineage& poet_side,
                       const std::vector<ControlRow>& rows) {
  const EnvEncoding& target = poet_side.pair.env.encoding;
  ControlsRose rose;
  rose.title = "Pair " + std::to_string(poet_side.pair.id) + ": POET's environment and the controls' closest solved";
  rose.poet_label = target.name;
  rose.poet = env_vector(target);
  for (const ControlRow& r : rows)
    rose.controls.push_back({r.mode + ", seed " + std::to_string(r.seed),
                             r.closest.distance ? std::optional<EnvVector>(r.closest.closest) : std::nullopt,
                             r.closest.distance});
  const Expected<std::string> bytes = render_controls_rose(format, rose);
  if (!bytes) return "cannot write " + path + ": " + bytes.error();
  const auto error = write_file_atomically(path, *bytes);
  return error ? "cannot write " + path + ": " + *error : "";
}

nlohmann::ordered_json comparison_json(const std::string& run_dir, const PoetLineage& poet_side,
                                       const std::vector<ControlRow>& rows) {
  const Pair& pair = poet_side.pair;
  nlohmann::ordered_json out;
  out["run_dir"] = run_dir;
  out["pair"] = pair.id;
  out["environment"] = pair.env.encoding.name;
  out["poet"] = {{"lineage_es_steps", poet_side.es_steps},
                 {"lineage_env_steps", poet_side.env_steps ? nlohmann::ordered_json(*poet_side.env_steps) : nullptr},
                 {"created", pair.created_iteration},
                 {"solved", pair.solved() ? nlohmann::ordered_json(pair.first_solved_iteration) : nullptr}};
  out["controls"] = nlohmann::ordered_json::array();
  for (const ControlRow& r : rows) out["controls"].push_back(json_of(r));
  return out;
}

// Writes the JSON document to path ('-': stdout); the exit code.
int write_json(const std::string& path, const nlohmann::ordered_json& doc) {
  const std::string text = doc.dump(2) + "\n";
  if (path == "-") {
    std::cout << text;
    return 0;
  }
  if (const auto error = write_file_atomically(path, text)) {
    std::cerr << "poet-controls: cannot write " << path << ": " << *error << "\n";
    return 1;
  }
  return 0;
}

// The comparison as a Markdown table, under a line on the pair and one on its lineage.
void print_comparison(const PoetLineage& poet_side, const std::vector<ControlRow>& rows) {
  const Pair& pair = poet_side.pair;
  const EnvEncoding& target = pair.env.encoding;
  std::printf("pair %d: %s (%s), created at %d, %s\n", pair.id, target.name.c_str(),
              std::string(level_label(target)).c_str(), pair.created_iteration,
              pair.solved() ? ("solved at " + std::to_string(pair.first_solved_iteration)).c_str() : "not solved");
  std::printf("POET's lineage: %lld ES steps, %s environment steps\n\n", static_cast<long long>(poet_side.es_steps),
              poet_side.env_steps ? number(static_cast<double>(*poet_side.env_steps) / 1e6, "%.1f M").c_str()
                                  : "(not recorded)");
  std::printf(
      "| control | seed | ES steps | environment steps | best on the target | solved | closest solved | "
      "normalised distance |\n|---|---|---|---|---|---|---|---|\n");
  for (const ControlRow& r : rows)
    std::printf(
        "| %s | %llu | %lld | %.1f M | %s | %s | %s | %s |\n", r.mode.c_str(), static_cast<unsigned long long>(r.seed),
        static_cast<long long>(r.es_steps), r.env_steps / 1e6, number(r.best_on_target, "%.1f").c_str(),
        r.solved_at_es_step ? ("yes, ES step " + std::to_string(*r.solved_at_es_step)).c_str() : "no",
        r.closest.distance ? r.closest.closest_env.c_str() : "nothing", number(r.closest.distance, "%.3f").c_str());
}

}  // namespace
}  // namespace poet

int run_tool(int argc, char** argv) {
  using namespace poet;
  Options o;
  if (auto code = parse_options(argc, argv, o)) return *code;
  const Expected<PictureFormat> format = rose_format(o.rose_path);
  if (!format) {
    std::cerr << "poet-controls: " << format.error() << "\n";
    return kExitUsage;
  }
  Expected<RunSnapshot> run = read_run_snapshot(o.run_dir);
  if (!run) {
    std::cerr << "poet-controls: " << run.error() << "\n";
    return kExitUsage;
  }
  const Pair* pair = run->state.find(o.pair_id);
  if (!pair || pair->env.encoding.is_cppn()) {
    std::cerr << "poet-controls: "
              << (pair ? "pair " + std::to_string(o.pair_id) + " has a CPPN course, which has no 5-vector"
                       : "no pair " + std::to_string(o.pair_id) + " in " + o.run_dir)
              << "\n";
    return kExitUsage;
  }
  const Expected<std::vector<ControlRow>> rows = control_rows(o.controls, pair->env.encoding);
  if (!rows) {
    std::cerr << "poet-controls: " << rows.error() << "\n";
    return kExitUsage;
  }
  const PoetLineage poet_side{*pair, lineage_es_steps(run->state, o.pair_id),
                              lineage_env_steps(run->state, o.pair_id, pair_env_steps_at(run->stats))};

  if (!o.rose_path.empty())
    if (std::string error = write_rose(o.rose_path, *format, poet_side, *rows); !error.empty()) {
      std::cerr << "poet-controls: " << error << "\n";
      return 1;
    }
  if (!o.json_path.empty()) return write_json(o.json_path, comparison_json(o.run_dir, poet_side, *rows));
  print_comparison(poet_side, *rows);
  return 0;
}

int main(int argc, char** argv) { return poet::output_checked("poet-controls", run_tool(argc, argv)); }
