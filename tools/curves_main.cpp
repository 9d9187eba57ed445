// poet-curves: learning curves (experiments/learning_curve.sh's curve.csv files) side by side — when each was solved,
// and one picture of their evaluation scores against ES steps, environment steps and wall time.
//   poet-curves [--plot FILE.png|svg] [--solved-score S] LABEL=CURVE.csv...

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "common/program/tool_flags.h"
#include "report/learning_curves.h"

namespace poet {
namespace {

void print_summary(const LearningCurve& curve, double solved_score) {
  const CurvePoint& last = curve.points.back();
  if (const CurvePoint* s = first_solved(curve, solved_score))
    std::printf("%-16s solved at ES step %lld: score %.1f, %.1f M environment steps, %lld rollouts, %.0f s\n",
                curve.label.c_str(), static_cast<long long>(s->es_step), s->score, s->env_steps / 1e6,
                static_cast<long long>(s->rollouts), s->wall_s);
  else
    std::printf("%-16s not solved by ES step %lld: score %.1f, %.1f M environment steps, %lld rollouts, %.0f s\n",
                curve.label.c_str(), static_cast<long long>(last.es_step), last.score, last.env_steps / 1e6,
                static_cast<long long>(last.rollouts), last.wall_s);
}

int run(int argc, char** argv) {
  CLI::App app{"Learning curves side by side: when each solved its course, and a picture of the scores"};
  std::vector<std::string> specs;
  std::string plot_path;
  double solved_score = 230;
  app.add_option("curves", specs,
                 "LABEL=CURVE.csv: a curve written by experiments/learning_curve.sh and its legend label")
      ->required();
  app.add_option("--plot", plot_path,
                 "Draw the scores against ES steps, environment steps and wall time here (default: none)");
  app.add_option("--solved-score", solved_score, "A course is solved when finished with at least this score")
      ->capture_default_str()
      ->check(CLI::Range(-1e6, 1e6));
  add_fingerprint_flag(app);
  if (auto code = parse_command_line(app, argc, argv)) return *code;

  std::vector<LearningCurve> curves;
  for (const std::string& spec : specs) {
    const size_t eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) {
      std::fprintf(stderr, "poet-curves: \"%s\" is not LABEL=CURVE.csv\n", spec.c_str());
      return kExitUsage;
    }
    Expected<LearningCurve> curve = read_learning_curve(spec.substr(eq + 1));
    if (!curve) {
      std::fprintf(stderr, "poet-curves: %s\n", curve.error().c_str());
      return kExitUsage;
    }
    curve->label = spec.substr(0, eq);
    curves.push_back(std::move(*curve));
  }
  for (const LearningCurve& curve : curves) print_summary(curve, solved_score);
  if (!plot_path.empty()) {
    const Expected<std::string> bytes = render_learning_curves(format_of(plot_path), curves, solved_score);
    const std::string error =
        bytes ? write_bytes(plot_path, *bytes) : "cannot draw " + plot_path + ": " + bytes.error();
    if (!error.empty()) {
      std::fprintf(stderr, "poet-curves: %s\n", error.c_str());
      return kExitError;
    }
  }
  return 0;
}

}  // namespace
}  // namespace poet

int main(int argc, char** argv) { return poet::output_checked("poet-curves", poet::run(argc, argv)); }
