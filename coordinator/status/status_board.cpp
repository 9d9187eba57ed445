#include "coordinator/status/status_board.h"

#include <algorithm>
#include <array>
#include <utility>

#include "coordinator/status/prometheus_text.h"
#include "coordinator/status/status_messages.h"
#include "engine/engine.h"
#include "run_directory/files/run_directory.h"
#include "simulation/enum_names.h"
#include "simulation/envgen/env_distance.h"

namespace poet {
namespace {

using SteadyTime = std::chrono::steady_clock::time_point;

// A counter's rate over the window: (newest − oldest) / seconds between them; 0 without two samples apart.
template <class Samples, class Field>
double rate(const Samples& samples, Field field) {
  if (samples.size() < 2) return 0;
  const double seconds = std::chrono::duration<double>(samples.back().at - samples.front().at).count();
  if (seconds <= 0) return 0;
  return static_cast<double>(field(samples.back()) - field(samples.front())) / seconds;
}

double seconds_between(SteadyTime from, SteadyTime to) { return std::chrono::duration<double>(to - from).count(); }

}  // namespace

std::string_view to_string(RunPhase phase) {
  static constexpr std::array<std::string_view, 5> kNames = {"starting", "running", "waiting_for_workers", "stopping",
                                                             "finished"};
  return enum_name(phase, kNames, "unknown");
}

StatusBoard::StatusBoard(std::filesystem::path run_dir, Clock clock)
    : run_dir_(std::move(run_dir)),
      clock_(clock ? std::move(clock) : Clock([] { return std::chrono::steady_clock::now(); })),
      created_(clock_()),
      stats_(run_dir_ / kStatsFile) {}

// ---------------------------------------------------------------------------------------------------------
// publishing

void StatusBoard::publish_run(const RunState& state, int last_checkpoint_iteration) {
  // the copy, outside the lock
  auto snapshot = std::make_shared<PublishedRun>();
  snapshot->mode = state.settings.mode;
  snapshot->seed = state.settings.seed;
  snapshot->next_iteration = state.next_iteration;
  snapshot->iterations = state.settings.iterations;
  snapshot->finished = run_complete(state);
  snapshot->counters = state.counters;
  snapshot->annecs = annecs_at(state, state.next_iteration - 1);
  snapshot->last_checkpoint_iteration = last_checkpoint_iteration;
  snapshot->pairs.reserve(state.pairs.size());
  for (const Pair& p : state.pairs) {
    PairInfo info;
    Pair& copy = info.pair;
    copy.id = p.id;
    copy.env = p.env;
    copy.created_iteration = p.created_iteration;
    copy.parent_id = p.parent_id;
    copy.initial_source_pair = p.initial_source_pair;
    copy.initial_by_proposal = p.initial_by_proposal;
    copy.admission_score = p.admission_score;
    copy.latest_score = p.latest_score;
    copy.latest_finished = p.latest_finished;
    copy.best_score = p.best_score;
    copy.best_iteration = p.best_iteration;
    copy.first_solved_iteration = p.first_solved_iteration;
    copy.retired_iteration = p.retired_iteration;
    copy.es_steps = p.es_steps;
    copy.transfers = p.transfers;
    copy.transfer_attempts = p.transfer_attempts;
    const EnvVector e = env_vector(p.env.encoding);
    info.difficulty_level = static_cast<int>(difficulty(e));
    raise_frontier(snapshot->frontier_admitted, e);
    if (p.solved()) {
      raise_frontier(snapshot->frontier_solved, e);
      snapshot->highest_level_solved = std::max(snapshot->highest_level_solved, info.difficulty_level);
    }
    snapshot->pairs.push_back(std::move(info));
  }
  const RateSample sample{clock_(), state.counters.rollouts, state.counters.env_steps};

  // the swap, under it (the previous snapshot is freed after, outside it)
  std::shared_ptr<const PublishedRun> previous;
  std::lock_guard lock(mutex_);
  previous = std::exchange(run_, std::move(snapshot));
  // counters that went back (a new state) start the window over
  if (!rate_samples_.empty() &&
      (sample.rollouts < rate_samples_.back().rollouts || sample.env_steps < rate_samples_.back().env_steps))
    rate_samples_.clear();
  rate_samples_.push_back(sample);
  while (rate_samples_.size() > kRateWindow) rate_samples_.pop_front();
}

void StatusBoard::publish_dispatch(DispatchView snapshot) {
  auto shared = std::make_shared<const DispatchView>(std::move(snapshot));
  const SteadyTime now = clock_();
  std::shared_ptr<const DispatchView> previous;  // freed after the lock is released
  std::lock_guard lock(mutex_);
  previous = std::exchange(dispatch_, std::move(shared));
  dispatch_at_ = now;
}

void StatusBoard::set_state(RunPhase phase, std::string note) {
  std::lock_guard lock(mutex_);
  phase_ = phase;
  note_ = std::move(note);
}

void StatusBoard::count_skipped_key_file() {
  std::lock_guard lock(mutex_);
  ++skipped_key_files_;
}

void StatusBoard::publish_phases(const PhaseSeconds& seconds, double waiting) {
  std::lock_guard lock(mutex_);
  phase_seconds_ = seconds;
  waiting_seconds_ = waiting;
}

void StatusBoard::publish_cache(int64_t episodes_saved, int64_t steps_saved) {
  std::lock_guard lock(mutex_);
  cached_episodes_ = episodes_saved;
  cached_env_steps_ = steps_saved;
}

BoardView StatusBoard::view() const {
  BoardView v;
  SteadyTime dispatch_at;
  {
    std::lock_guard lock(mutex_);
    v.run = run_;
    v.dispatch = dispatch_;
    dispatch_at = dispatch_at_;
    v.phase = phase_;
    v.note = note_;
    v.rollouts_per_s = rate(rate_samples_, [](const RateSample& s) { return s.rollouts; });
    v.env_steps_per_s = rate(rate_samples_, [](const RateSample& s) { return s.env_steps; });
    v.skipped_key_files = skipped_key_files_;
    v.cached_episodes = cached_episodes_;
    v.cached_env_steps = cached_env_steps_;
    v.phase_seconds = phase_seconds_;
    v.waiting_seconds = waiting_seconds_;
  }
  const SteadyTime now = clock_();
  v.uptime_s = seconds_between(created_, now);
  v.dispatch_age_s = std::max(0.0, seconds_between(dispatch_at, now));
  return v;
}

// ---------------------------------------------------------------------------------------------------------
// reading: the renderers over a view

status::Status StatusBoard::status() const { return status_message(view(), run_dir_); }

status::PairList StatusBoard::pairs() const { return pair_list(view()); }

bool StatusBoard::has_pair(int id) const {
  const BoardView v = view();
  return v.run && std::any_of(v.run->pairs.begin(), v.run->pairs.end(),
                              [id](const PairInfo& info) { return info.pair.id == id; });
}

std::optional<status::PairDetail> StatusBoard::pair(int id) const {
  const BoardView v = view();
  if (!v.run) return std::nullopt;
  std::vector<StatsRow> scores;
  {
    std::lock_guard lock(stats_mutex_);
    scores = stats_.rows_of(id);
  }
  return pair_detail(v, id, scores);
}

status::Archive StatusBoard::archive() const { return archive_message(view()); }

status::WorkerList StatusBoard::workers() const { return worker_list(view()); }

Expected<status::EventList> StatusBoard::events(int64_t since, int64_t limit) const {
  return event_list(run_dir_ / kEventsFile, std::max<int64_t>(since, 0),
                    std::clamp<int64_t>(limit, 1, kMaxEventsPerPage));
}

std::string StatusBoard::metrics_text() const { return prometheus_text(view()); }

}  // namespace poet
