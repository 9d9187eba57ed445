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

}  // namespace

std::string prometheus_text(const BoardView& v) {
  std::string text;
  auto family = [&](const char* name, const char* type, const char* help) {
    text += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
  };
  auto sample = [&](const std::string& name, auto value) { text += name + " " + std::to_string(value) + "\n"; };

  const PublishedRun empty;
  const PublishedRun& run = v.run ? *v.run : empty;
  int active = 0, solved = 0;
  for (const PairInfo& info : run.pairs) {
    active += info.pair.active() ? 1 : 0;
    solved += info.pair.solved() ? 1 : 0;
  }
  family("poet_iteration", "gauge", "The iteration the run does next.");
  sample("poet_iteration", run.next_iteration);
  family("poet_iterations_limit", "gauge", "The run stops before this iteration.");
  sample("poet_iterations_limit", run.iterations);
  family("poet_last_checkpoint_iteration", "gauge", "The next iteration of the last checkpoint written.");
  sample("poet_last_checkpoint_iteration", run.last_checkpoint_iteration);
  family("poet_run_finished", "gauge", "1 when the run reached its stopping rule.");
  sample("poet_run_finished", run.finished ? 1 : 0);
  family("poet_pairs_created", "gauge", "Pairs ever created (the archive).");
  sample("poet_pairs_created", run.pairs.size());
  family("poet_pairs_active", "gauge", "Active environment-agent pairs.");
  sample("poet_pairs_active", active);
  family("poet_pairs_solved", "gauge", "Pairs whose environment was ever solved.");
  sample("poet_pairs_solved", solved);
  family("poet_rollouts_total", "counter", "Rollouts since the run began.");
  sample("poet_rollouts_total", run.counters.rollouts);
  family("poet_env_steps_total", "counter", "Environment steps since the run began.");
  sample("poet_env_steps_total", run.counters.env_steps);
  family("poet_annecs", "gauge",
         "ANNECS (accumulated number of novel environments created and solved) as of the last iteration done, by "
         "definition. at_admission: environments admitted by reproduction and solved since, counted when solved. "
         "at_archiving: environments retired that had been solved by then, counted at retirement.");
  sample("poet_annecs{definition=\"at_admission\"}", run.annecs.at_admission);
  sample("poet_annecs{definition=\"at_archiving\"}", run.annecs.at_archiving);

  const DispatchView no_dispatch;
  const DispatchView& dispatch = v.dispatch ? *v.dispatch : no_dispatch;
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
    family(one.name, one.type, one.help);
    sample(one.name, one.value);
  }
  family("poet_dropped_frames_total", "counter", "Frames and Hellos the dispatcher dropped or refused, by reason.");
  std::map<std::string, int64_t> dropped;
  for (const char* reason : kDropReasonNames) dropped[reason] = 0;
  for (const auto& [reason, count] : dispatch.dropped_frames) dropped[reason] = count;
  for (const auto& [reason, count] : dropped)
    sample("poet_dropped_frames_total{reason=\"" + label_value(reason) + "\"}", count);
  family("poet_skipped_key_files_total", "counter",
         "Files in the CURVE authorized/ folder skipped because they hold no key, each counted once when found.");
  sample("poet_skipped_key_files_total", v.skipped_key_files);
  family("poet_cached_episodes_total", "counter",
         "Episodes the loop asked for again and the score cache answered without running them, since the "
         "coordinator started (the run's rollout counters include them).");
  sample("poet_cached_episodes_total", v.cached_episodes);
  family("poet_cached_env_steps_total", "counter", "The environment steps of those episodes.");
  sample("poet_cached_env_steps_total", v.cached_env_steps);
  family("poet_phase_seconds_total", "counter",
         "Seconds this coordinator spent in each phase of an iteration, as of its last checkpoint (wall_times.csv "
         "keeps them per iteration; the time between iterations is in none).");
  for (size_t k = 0; k < kPhaseNames.size(); ++k) {
    char value[32];
    std::snprintf(value, sizeof value, "%.3f", v.phase_seconds[k]);
    text += "poet_phase_seconds_total{phase=\"" + std::string(kPhaseNames[k]) + "\"} " + value + "\n";
  }
  family("poet_waiting_seconds_total", "counter",
         "Of those seconds, the ones the run loop spent waiting for rollouts; the rest is the coordinator's own "
         "serial work.");
  char waiting[32];
  std::snprintf(waiting, sizeof waiting, "%.3f", v.waiting_seconds);
  text += std::string("poet_waiting_seconds_total ") + waiting + "\n";

  family("poet_uptime_seconds", "gauge", "Seconds since the coordinator started.");
  char uptime[32];
  std::snprintf(uptime, sizeof uptime, "%.3f", v.uptime_s);
  text += std::string("poet_uptime_seconds ") + uptime + "\n";
  return text;
}

}  // namespace poet
