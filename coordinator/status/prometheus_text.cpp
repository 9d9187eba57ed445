#include "coordinator/status/prometheus_text.h"

#include <cstdio>
#include <map>

#include "coordinator/dispatch/drop_reason.h"

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

// The exposition text, written a metric family at a time: its HELP and TYPE lines, then its samples.
struct Exposition {
  std::string text;

  void family(const char* name, const char* type, const char* help) {
    text += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
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
  out.family("poet_iteration", "gauge", "The iteration the run does next.");
  out.sample("poet_iteration", run.next_iteration);
  out.family("poet_iterations_limit", "gauge", "The run stops before this iteration.");
  out.sample("poet_iterations_limit", run.iterations);
  out.family("poet_last_checkpoint_iteration", "gauge", "The next iteration of the last checkpoint written.");
  out.sample("poet_last_checkpoint_iteration", run.last_checkpoint_iteration);
  out.family("poet_run_finished", "gauge", "1 when the run reached its stopping rule.");
  out.sample("poet_run_finished", run.finished ? 1 : 0);
  out.family("poet_pairs_created", "gauge", "Pairs ever created (the archive).");
  out.sample("poet_pairs_created", run.pairs.size());
  out.family("poet_pairs_active", "gauge", "Active environment-agent pairs.");
  out.sample("poet_pairs_active", active);
  out.family("poet_pairs_solved", "gauge", "Pairs whose environment was ever solved.");
  out.sample("poet_pairs_solved", solved);
  out.family("poet_rollouts_total", "counter", "Rollouts since the run began.");
  out.sample("poet_rollouts_total", run.counters.rollouts);
  out.family("poet_env_steps_total", "counter", "Environment steps since the run began.");
  out.sample("poet_env_steps_total", run.counters.env_steps);
  out.family("poet_annecs", "gauge",
             "ANNECS (accumulated number of novel environments created and solved) as of the last iteration done, "
             "by definition. at_admission: environments admitted by reproduction and solved since, counted when "
             "solved. at_archiving: environments retired that had been solved by then, counted at retirement.");
  out.sample("poet_annecs{definition=\"at_admission\"}", run.annecs.at_admission);
  out.sample("poet_annecs{definition=\"at_archiving\"}", run.annecs.at_archiving);
  out.family("poet_obstacle_frontier", "gauge",
             "Table 1's measures (roughness, the top of the gap range, the top of the stump range): the largest value "
             "among the environments solved so far, and among those admitted.");
  for (size_t i = 0; i < kObstacleMeasureNames.size(); ++i) {
    const std::string measure = std::string("measure=\"") + kObstacleMeasureNames[i] + "\"";
    out.measure("poet_obstacle_frontier{" + measure + ",among=\"solved\"}", run.frontier_solved[i]);
    out.measure("poet_obstacle_frontier{" + measure + ",among=\"admitted\"}", run.frontier_admitted[i]);
  }
  out.family("poet_highest_level_solved", "gauge",
             "The hardest difficulty level solved so far: 0 easy, 1 challenging, 2 very challenging, 3 extremely "
             "challenging; -1 before any solve.");
  out.sample("poet_highest_level_solved", run.highest_level_solved);
}

// The dispatcher's workers, queue and counts, each a family of one sample.
void write_dispatch(Exposition& out, const DispatchView& dispatch) {
  struct Series {
    const char* name;
    const char* type;
    const char* help;
    int64_t value;
  };
  const Series series[] = {
      {"poet_workers", "gauge", "Connected workers.", static_cast<int64_t>(dispatch.workers.size())},
      {"poet_queue_depth", "gauge", "Jobs waiting for a worker.", dispatch.queue_depth},
      {"poet_in_flight_jobs", "gauge", "Jobs held by workers.", dispatch.in_flight_jobs},
      {"poet_workers_joined_total", "counter", "Workers welcomed since the coordinator started.",
       dispatch.workers_joined},
      {"poet_workers_lost_total", "counter",
       "Workers removed for being silent longer than the liveness window, or because a send to them failed.",
       dispatch.workers_lost},
      {"poet_backup_jobs_total", "counter",
       "Jobs also sent to a second worker because their first held them far longer than the batch's jobs take.",
       dispatch.backup_jobs},
      {"poet_leases_expired_total", "counter",
       "Jobs taken back from a worker that had never returned a result, once their lease ran out.",
       dispatch.leases_expired},
      {"poet_workers_demoted_total", "counter",
       "Workers that never returned a result and let a lease expire or returned an error: given no more jobs.",
       dispatch.workers_demoted},
      {"poet_verified_jobs_total", "counter",
       "Answers of workers found right, bit for bit, by a second worker or the coordinator.", dispatch.verified_jobs},
      {"poet_wrong_workers_total", "counter",
       "Workers refused because their results differed from two other answers (another worker's or the "
       "coordinator's own).",
       dispatch.wrong_workers},
      {"poet_coordinator_checks_total", "counter",
       "Jobs the coordinator ran itself to check or decide between answers, no other worker being able to.",
       dispatch.coordinator_checks},
      {"poet_rollbacks_total", "counter",
       "Times the run went back to a checkpoint computed before a worker found wrong had unchecked answers taken.",
       dispatch.rollbacks},
  };
  for (const Series& one : series) {
    out.family(one.name, one.type, one.help);
    out.sample(one.name, one.value);
  }
}

// A sample per drop reason, zero for those that have not happened.
void write_dropped_frames(Exposition& out, const DispatchView& dispatch) {
  out.family("poet_dropped_frames_total", "counter", "Frames and Hellos the dispatcher dropped or refused, by reason.");
  std::map<std::string, int64_t> dropped;
  for (const char* reason : kDropReasonNames) dropped[reason] = 0;
  for (const auto& [reason, count] : dispatch.dropped_frames) dropped[reason] = count;
  for (const auto& [reason, count] : dropped)
    out.sample("poet_dropped_frames_total{reason=\"" + label_value(reason) + "\"}", count);
}

// The coordinator's own: key files skipped, the score cache, and where its time went.
void write_coordinator(Exposition& out, const BoardView& v) {
  out.family("poet_skipped_key_files_total", "counter",
             "Files in the CURVE authorized/ folder skipped because they hold no key, each counted once when found.");
  out.sample("poet_skipped_key_files_total", v.skipped_key_files);
  out.family("poet_cached_episodes_total", "counter",
             "Episodes the loop asked for again and the score cache answered without running them, since the "
             "coordinator started (the run's rollout counters include them).");
  out.sample("poet_cached_episodes_total", v.cached_episodes);
  out.family("poet_cached_env_steps_total", "counter", "The environment steps of those episodes.");
  out.sample("poet_cached_env_steps_total", v.cached_env_steps);
  out.family("poet_phase_seconds_total", "counter",
             "Seconds this coordinator spent in each phase of an iteration, as of its last checkpoint (wall_times.csv "
             "keeps them per iteration; the time between iterations is in none).");
  for (size_t k = 0; k < kPhaseNames.size(); ++k)
    out.seconds("poet_phase_seconds_total{phase=\"" + std::string(kPhaseNames[k]) + "\"}", v.phase_seconds[k]);
  out.family("poet_waiting_seconds_total", "counter",
             "Of those seconds, the ones the run loop spent waiting for rollouts; the rest is the coordinator's own "
             "serial work.");
  out.seconds("poet_waiting_seconds_total", v.waiting_seconds);

  out.family("poet_uptime_seconds", "gauge", "Seconds since the coordinator started.");
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
