#include "python/run_view.h"

#include <stdexcept>

#include "common/formats/envgen/env_json.h"
#include "run_directory/reading/coverage.h"
#include "run_directory/reading/report_json.h"
#include "run_directory/reading/run_metrics.h"
#include "run_directory/reading/run_snapshot.h"

namespace poet::python {

RunView read_run_view(const std::string& dir) {
  Expected<RunSnapshot> run = read_run_snapshot(dir);
  if (!run) throw std::invalid_argument(run.error());
  const RunMetrics metrics = compute_run_metrics(*run);
  const Coverage coverage = compute_coverage(run->state);
  RunView view;
  view.report_json = report_json(*run, metrics, coverage).dump();
  nlohmann::json events = nlohmann::json::array();
  for (const nlohmann::json& e : run->events) events.push_back(e);
  view.events_json = events.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  view.config_text = run->config_text;
  view.stats_csv = std::move(run->stats_text);
  view.next_iteration = run->state.next_iteration;
  view.live = run->live;
  for (const Pair& p : run->state.pairs) view.pairs.push_back({p.id, env_def_json_text(p.env), p.theta, p.best_theta});
  return view;
}

}  // namespace poet::python
