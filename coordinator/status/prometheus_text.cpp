#include "coordinator/status/prometheus_text.h"

#include <cstdio>
#include <map>

#include "coordinator/dispatch/drop_reason.h"
#include "coordinator/status/metric_families.h"

namespace poet {
namespace {

// A Prometheus label value: backslash, double quote and newline escaped.
std::string label_value(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out;
}

// The exposition text, written a metric family at a time: its HELP and TYPE lines (from metric_families.h),
// then its samples.
struct Exposition {
  std::string text;

  void family(const MetricFamily& declared) {
    const std::string name(declared.name);
    text += "# HELP " + name + " " + std::string(declared.help) + "\n# TYPE " + name + " " +
            std::string(declared.type) + "\n";
  }
  template <class T>
  void sample(const std::string& name, T value) {
    text += name + " " + std::to_string(value) + "\n";
  }
  // a sample of a measure in the environments' own units (one decimal in practice), without trailing zeros
  void measure(const std::string& name, double value) {
    char formatted[32];
    std::snprintf(formatted, sizeof formatted, "%.6g", value);
    text += name + " " + formatted + "\n";
  }
  // a sample in seconds, to the millisecond
  void seconds(const std::string& name, double value) {
    char formatted[32];
    std::snprintf(formatted, sizeof formatted, "%.3f", value);
    text += name + " " + formatted + "\n";
  }
};

// The run as last published: progress, the archive, the counters and ANNECS.
void write_run(Exposition& out, const PublishedRun& run) {
  int active = 0, solved = 0;
  for (const PairInfo& info : run.pairs) {
    active += info.pair.active() ? 1 : 0;
    solved += info.pair.solved() ? 1 : 0;
  }
  out.family(metric_family("poet_iteration"));
  out.sample("poet_iteration", run.next_iteration);
  out.family(metric_family("poet_iterations_limit"));
  out.sample("poet_iterations_limit", run.iterations);
  out.family(metric_family("poet_last_checkpoint_iteration"));
  out.sample("poet_last_checkpoint_iteration", run.last_checkpoint_iteration);
  out.family(metric_family("poet_run_finished"));
  out.sample("poet_run_finished", run.finished ? 1 : 0);
  out.family(metric_family("poet_pairs_created"));
  out.sample("poet_pairs_created", run.pairs.size());
  out.family(metric_family("poet_pairs_active"));
  out.sample("poet_pairs_active", active);
  out.family(metric_family("poet_pairs_solved"));
  out.sample("poet_pairs_solved", solved);
  out.family(metric_family("poet_rollouts_total"));
  out.sample("poet_rollouts_total", run.counters.rollouts);
  out.family(metric_family("poet_env_steps_total"));
  out.sample("poet_env_steps_total", run.counters.env_steps);
  out.family(metric_family("poet_annecs"));
  out.sample("poet_annecs{definition=\"at_admission\"}", run.annecs.at_admission);
  out.sample("poet_annecs{definition=\"at_archiving\"}", run.annecs.at_archiving);
  out.family(metric_family("poet_obstacle_frontier"));
  for (size_t i = 0; i < kObstacleMeasureNames.size(); ++i) {
    const std::string measure = std::string("measure=\"") + kObstacleMeasureNames[i] + "\"";
    out.measure("poet_obstacle_frontier{" + measure + ",among=\"solved\"}", run.frontier_solved[i]);
    out.measure("poet_obstacle_frontier{" + measure + ",among=\"admitted\"}", run.frontier_admitted[i]);
  }
  out.family(metric_family("poet_highest_level_solved"));
  out.sample("poet_highest_level_solved", run.highest_level_solved);
}

// The dispatcher's workers, queue and counts, each a family of one sample.
void write_dispatch(Exposition& out, const DispatchView& dispatch) {
  struct Series {
    const MetricFamily& family;
    int64_t value;
  };
  const Series series[] = {
      {metric_family("poet_workers"), static_cast<int64_t>(dispatch.workers.size())},
      {metric_family("poet_queue_depth"), dispatch.queue_depth},
      {metric_family("poet_in_flight_jobs"), dispatch.in_flight_jobs},
      {metric_family("poet_workers_joined_total"), dispatch.workers_joined},
      {metric_family("poet_workers_lost_total"), dispatch.workers_lost},
      {metric_family("poet_backup_jobs_total"), dispatch.backup_jobs},
      {metric_family("poet_leases_expired_total"), dispatch.leases_expired},
      {metric_family("poet_workers_demoted_total"), dispatch.workers_demoted},
      {metric_family("poet_verified_jobs_total"), dispatch.verified_jobs},
      {metric_family("poet_wrong_workers_total"), dispatch.wrong_workers},
      {metric_family("poet_coordinator_checks_total"), dispatch.coordinator_checks},
      {metric_family("poet_rollbacks_total"), dispatch.rollbacks},
  };
  for (const Series& one : series) {
    out.family(one.family);
    out.sample(std::string(one.family.name), one.value);
  }
}

// A sample per drop reason, zero for those that have not happened.
void write_dropped_frames(Exposition& out, const DispatchView& dispatch) {
  out.family(metric_family("poet_dropped_frames_total"));
  std::map<std::string, int64_t> dropped;
  for (const char* reason : kDropReasonNames) dropped[reason] = 0;
  for (const auto& [reason, count] : dispatch.dropped_frames) dropped[reason] = count;
  for (const auto& [reason, count] : dropped)
    out.sample("poet_dropped_frames_total{reason=\"" + label_value(reason) + "\"}", count);
}

// The coordinator's own: key files skipped, the score cache, and where its time went.
void write_coordinator(Exposition& out, const BoardView& v) {
  out.family(metric_family("poet_skipped_key_files_total"));
  out.sample("poet_skipped_key_files_total", v.skipped_key_files);
  out.family(metric_family("poet_cached_episodes_total"));
  out.sample("poet_cached_episodes_total", v.cached_episodes);
  out.family(metric_family("poet_cached_env_steps_total"));
  out.sample("poet_cached_env_steps_total", v.cached_env_steps);
  out.family(metric_family("poet_phase_seconds_total"));
  for (size_t k = 0; k < kPhaseNames.size(); ++k)
    out.seconds("poet_phase_seconds_total{phase=\"" + std::string(kPhaseNames[k]) + "\"}", v.phase_seconds[k]);
  out.family(metric_family("poet_waiting_seconds_total"));
  out.seconds("poet_waiting_seconds_total", v.waiting_seconds);

  out.family(metric_family("poet_uptime_seconds"));
  out.seconds("poet_uptime_seconds", v.uptime_s);
}

}  // namespace

std::string prometheus_text(const BoardView& v) {
  const PublishedRun empty;
  const DispatchView no_dispatch;
  Exposition out;
  write_run(out, v.run ? *v.run : empty);
  write_dispatch(out, v.dispatch ? *v.dispatch : no_dispatch);
  write_dropped_frames(out, v.dispatch ? *v.dispatch : no_dispatch);
  write_coordinator(out, v);
  return out.text;
}

}  // namespace poet
