#include "run_directory/reading/run_suite.h"

#include <cstdio>
#include <map>
#include <tuple>

#include "common/formats/suite_score_json.h"
#include "common/formats/suite_score_table.h"

namespace poet {
namespace {

// (finished, mean progress, mean return): larger is better; the earlier candidate wins a tie. Progress before the
// return, which ranks standing still above walking halfway and falling.
template <class Score>
bool better(const Score& a, const Score& b) {
  return std::make_tuple(a.finished(), a.mean_progress(), a.mean_return()) >
         std::make_tuple(b.finished(), b.mean_progress(), b.mean_return());
}

}  // namespace

std::vector<SuiteCandidate> suite_candidates(const RunState& state) {
  std::vector<SuiteCandidate> out;
  for (const Pair& p : state.pairs) {
    const std::string label = "pair " + std::to_string(p.id);
    out.push_back({p.id, false, label, p.theta});
    if (!p.best_theta.empty() && p.best_theta != p.theta) out.push_back({p.id, true, label + " best", p.best_theta});
  }
  return out;
}

RunSuite evaluate_run_on_suite(const RunState& state, const CourseSuite& suite, int threads) {
  RunSuite run{suite_candidates(state), {}, 0, std::vector<size_t>(suite.groups.size(), 0)};
  // a θ that several pairs hold (a transfer copies one) is run once: the episodes are a function of θ
  std::map<std::vector<double>, size_t> first_with;
  for (size_t i = 0; i < run.candidates.size(); ++i) {
    const auto [it, fresh] = first_with.emplace(run.candidates[i].theta, i);
    run.scores.push_back(fresh ? run_suite(Mlp(run.candidates[i].theta), suite, state.settings.episodes.walker,
                                           state.settings.episodes.max_steps, threads)
                               : run.scores[it->second]);
  }
  for (size_t i = 1; i < run.scores.size(); ++i) {
    const SuiteScore& s = run.scores[i];
    const SuiteScore& b = run.scores[run.best];
    if (better(s, b)) run.best = i;
    for (size_t g = 0; g < suite.groups.size(); ++g) {
      const GroupScore& x = s.groups[g];
      const GroupScore& y = run.scores[run.best_per_group[g]].groups[g];
      if (better(x, y)) run.best_per_group[g] = i;
    }
  }
  return run;
}

std::string run_suite_table(const RunSuite& run) {
  if (run.scores.empty()) return "the run has no agents to evaluate\n";
  std::string out = suite_rows_header(run.scores.front());
  for (size_t i = 0; i < run.candidates.size(); ++i) out += suite_row(run.candidates[i].label, run.scores[i]);
  const SuiteScore& best = run.scores[run.best];
  char figures[128];
  std::snprintf(figures, sizeof figures, " (%d of %d finished, mean progress %.1f%%, mean return %.2f)\n",
                best.finished(), best.episodes(), 100 * best.mean_progress(), best.mean_return());
  out += "best single agent on " + best.suite + ": " + run.candidates[run.best].label + figures;
  for (size_t g = 0; g < run.best_per_group.size(); ++g) {
    const GroupScore& score = run.scores[run.best_per_group[g]].groups[g];
    std::snprintf(figures, sizeof figures, " (%d of %zu finished, mean progress %.1f%%, mean return %.2f)\n",
                  score.finished(), score.episodes.size(), 100 * score.mean_progress(), score.mean_return());
    out += "best on " + score.group + ": " + run.candidates[run.best_per_group[g]].label + figures;
  }
  return out;
}

nlohmann::json run_suite_json(const RunSuite& run, const CourseSuite& suite, const std::string& run_dir,
                              bool episodes) {
  nlohmann::json candidates = nlohmann::json::array();
  for (size_t i = 0; i < run.candidates.size(); ++i) {
    const SuiteCandidate& c = run.candidates[i];
    candidates.push_back({{"label", c.label},
                          {"pair", c.pair},
                          {"best_theta", c.best_theta},
                          {"score", episodes ? to_json(run.scores[i], suite) : summary_json(run.scores[i])}});
  }
  nlohmann::json doc = {{"suite", suite.name}, {"run_dir", run_dir}, {"candidates", candidates}};
  if (run.scores.empty()) return doc;
  doc["best"] = run.candidates[run.best].label;
  for (size_t g = 0; g < run.best_per_group.size(); ++g)
    doc["best_per_group"][suite.groups[g].name] = run.candidates[run.best_per_group[g]].label;
  return doc;
}

}  // namespace poet
