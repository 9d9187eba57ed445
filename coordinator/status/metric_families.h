#pragma once
// Every metric family GET /metrics serves, as data: name, type, labels with their values, HELP, and the group the
// reference files it under. prometheus_text.cpp writes a family only through metric_family(name), which is
// consteval: a family missing from this table does not compile. status_reference.cpp writes
// docs/reference/metrics.md from the same table.

#include <array>
#include <span>
#include <string_view>

#include "coordinator/dispatch/drop_reason.h"
#include "run_directory/files/wall_times.h"
#include "simulation/envgen/env_distance.h"

namespace poet {

// A label and every value it takes.
struct MetricLabel {
  std::string_view name;
  std::span<const std::string_view> values;
};

// The reference's sections.
enum class MetricGroup { kRun, kDispatch, kVerification, kCoordinator };

struct MetricFamily {
  std::string_view name;
  std::string_view type;  // "gauge" or "counter"
  MetricGroup group;
  std::span<const MetricLabel> labels;  // empty: one sample, unlabelled
  std::string_view help;
};

namespace metric_table {

// A code array of names (const char* or string_view) as string_views, at compile time.
template <auto& names>
constexpr auto as_views() {
  std::array<std::string_view, names.size()> out{};
  for (size_t i = 0; i < names.size(); ++i) out[i] = names[i];
  return out;
}

inline constexpr std::array<std::string_view, 2> kAnnecsDefinitions = {"at_admission", "at_archiving"};
inline constexpr auto kMeasures = as_views<kObstacleMeasureNames>();
inline constexpr std::array<std::string_view, 2> kAmong = {"solved", "admitted"};
inline constexpr auto kDropReasons = as_views<kDropReasonNames>();
inline constexpr auto kPhases = as_views<kPhaseNames>();

inline constexpr MetricLabel kAnnecsLabels[] = {{"definition", kAnnecsDefinitions}};
inline constexpr MetricLabel kFrontierLabels[] = {{"measure", kMeasures}, {"among", kAmong}};
inline constexpr MetricLabel kDropLabels[] = {{"reason", kDropReasons}};
inline constexpr MetricLabel kPhaseLabels[] = {{"phase", kPhases}};

}  // namespace metric_table

// In the order /metrics writes them.
inline constexpr MetricFamily kMetricFamilies[] = {
    // the run as last published: progress, the archive, the counters and ANNECS
    {"poet_iteration", "gauge", MetricGroup::kRun, {}, "The iteration the run does next."},
    {"poet_iterations_limit", "gauge", MetricGroup::kRun, {}, "The run stops before this iteration."},
    {"poet_last_checkpoint_iteration",
     "gauge",
     MetricGroup::kRun,
     {},
     "The next iteration of the last checkpoint written."},
    {"poet_run_finished", "gauge", MetricGroup::kRun, {}, "1 when the run reached its stopping rule."},
    {"poet_pairs_created", "gauge", MetricGroup::kRun, {}, "Pairs ever created (the archive)."},
    {"poet_pairs_active", "gauge", MetricGroup::kRun, {}, "Active environment-agent pairs."},
    {"poet_pairs_solved", "gauge", MetricGroup::kRun, {}, "Pairs whose environment was ever solved."},
    {"poet_rollouts_total", "counter", MetricGroup::kRun, {}, "Rollouts since the run began."},
    {"poet_env_steps_total", "counter", MetricGroup::kRun, {}, "Environment steps since the run began."},
    {"poet_annecs", "gauge", MetricGroup::kRun, metric_table::kAnnecsLabels,
     "ANNECS (accumulated number of novel environments created and solved) as of the last iteration done, "
     "by definition. at_admission: environments admitted by reproduction and solved since, counted when "
     "solved. at_archiving: environments retired that had been solved by then, counted at retirement."},
    {"poet_obstacle_frontier", "gauge", MetricGroup::kRun, metric_table::kFrontierLabels,
     "Table 1's measures (roughness, the top of the gap range, the top of the stump range): the largest value "
     "among the environments solved so far, and among those admitted."},
    {"poet_highest_level_solved",
     "gauge",
     MetricGroup::kRun,
     {},
     "The hardest difficulty level solved so far: 0 easy, 1 challenging, 2 very challenging, 3 extremely "
     "challenging; -1 before any solve."},
    // the dispatcher's workers, queue and counts
    {"poet_workers", "gauge", MetricGroup::kDispatch, {}, "Connected workers."},
    {"poet_queue_depth", "gauge", MetricGroup::kDispatch, {}, "Jobs waiting for a worker."},
    {"poet_in_flight_jobs", "gauge", MetricGroup::kDispatch, {}, "Jobs held by workers."},
    {"poet_workers_joined_total",
     "counter",
     MetricGroup::kDispatch,
     {},
     "Workers welcomed since the coordinator started."},
    {"poet_workers_lost_total",
     "counter",
     MetricGroup::kDispatch,
     {},
     "Workers removed for being silent longer than the liveness window, or because a send to them failed."},
    {"poet_backup_jobs_total",
     "counter",
     MetricGroup::kDispatch,
     {},
     "Jobs also sent to a second worker because their first held them far longer than the batch's jobs take."},
    {"poet_leases_expired_total",
     "counter",
     MetricGroup::kDispatch,
     {},
     "Jobs taken back from a worker that had never returned a result, once their lease ran out."},
    {"poet_workers_demoted_total",
     "counter",
     MetricGroup::kVerification,
     {},
     "Workers that never returned a result and let a lease expire or returned an error: given no more jobs."},
    {"poet_verified_jobs_total",
     "counter",
     MetricGroup::kVerification,
     {},
     "Answers of workers found right, bit for bit, by a second worker or the coordinator."},
    {"poet_wrong_workers_total",
     "counter",
     MetricGroup::kVerification,
     {},
     "Workers refused because their results differed from two other answers (another worker's or the "
     "coordinator's own)."},
    {"poet_coordinator_checks_total",
     "counter",
     MetricGroup::kVerification,
     {},
     "Jobs the coordinator ran itself to check or decide between answers, no other worker being able to."},
    {"poet_rollbacks_total",
     "counter",
     MetricGroup::kVerification,
     {},
     "Times the run went back to a checkpoint computed before a worker found wrong had unchecked answers taken."},
    {"poet_dropped_frames_total", "counter", MetricGroup::kDispatch, metric_table::kDropLabels,
     "Frames and Hellos the dispatcher dropped or refused, by reason."},
    // the coordinator's own: key files skipped, the score cache, where its time went
    {"poet_skipped_key_files_total",
     "counter",
     MetricGroup::kVerification,
     {},
     "Files in the CURVE authorized/ folder skipped because they hold no key, each counted once when found."},
    {"poet_cached_episodes_total",
     "counter",
     MetricGroup::kCoordinator,
     {},
     "Episodes the loop asked for again and the score cache answered without running them, since the "
     "coordinator started (the run's rollout counters include them)."},
    {"poet_cached_env_steps_total",
     "counter",
     MetricGroup::kCoordinator,
     {},
     "The environment steps of those episodes."},
    {"poet_phase_seconds_total", "counter", MetricGroup::kCoordinator, metric_table::kPhaseLabels,
     "Seconds this coordinator spent in each phase of an iteration, as of its last checkpoint (wall_times.csv "
     "keeps them per iteration; the time between iterations is in none)."},
    {"poet_waiting_seconds_total",
     "counter",
     MetricGroup::kCoordinator,
     {},
     "Of those seconds, the ones the run loop spent waiting for rollouts; the rest is the coordinator's own "
     "serial work."},
    {"poet_uptime_seconds", "gauge", MetricGroup::kCoordinator, {}, "Seconds since the coordinator started."},
};

// The declared family of this name; a name the table lacks is a compile error where it is used.
consteval const MetricFamily& metric_family(std::string_view name) {
  for (const MetricFamily& family : kMetricFamilies)
    if (family.name == name) return family;
  throw "a metric family missing from kMetricFamilies";  // in a consteval function: a compile error
}

}  // namespace poet
