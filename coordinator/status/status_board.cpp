#include "status/status_board.h"

#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "csv_fields.h"
#include "envgen/env_distance.h"
#include "envgen/env_proto.h"
#include "poet/engine.h"
#include "run/run_directory.h"
#include "text_format.h"

namespace poet {
namespace {

using SteadyTime = std::chrono::steady_clock::time_point;

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

// A counter's rate over the window: (newest − oldest) / seconds between them; 0 without two samples apart.
template <class Samples, class Field>
double rate(const Samples& samples, Field field) {
  if (samples.size() < 2) return 0;
  const double seconds = std::chrono::duration<double>(samples.back().at - samples.front().at).count();
  if (seconds <= 0) return 0;
  return static_cast<double>(field(samples.back()) - field(samples.front())) / seconds;
}

}  // namespace

std::string valid_utf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    size_t length = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool ok = length > 0 && i + length <= text.size();
    for (size_t k = 1; ok && k < length; ++k) ok = (static_cast<unsigned char>(text[i + k]) >> 6) == 0x2;
    if (ok && length > 1) {  // no overlong forms, no surrogates, nothing beyond U+10FFFF
      const auto c1 = static_cast<unsigned char>(text[i + 1]);
      if (length == 2) ok = c >= 0xC2;
      if (length == 3) ok = (c != 0xE0 || c1 >= 0xA0) && (c != 0xED || c1 < 0xA0);
      if (length == 4) ok = c <= 0xF4 && (c != 0xF0 || c1 >= 0x90) && (c != 0xF4 || c1 < 0x90);
    }
    if (ok) {
      out.append(text.substr(i, length));
      i += length;
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

std::string_view to_string(RunPhase phase) {
  switch (phase) {
    case RunPhase::kStarting:
      return "starting";
    case RunPhase::kRunning:
      return "running";
    case RunPhase::kWaitingForWorkers:
      return "waiting_for_workers";
    case RunPhase::kStopping:
      return "stopping";
    case RunPhase::kFinished:
      return "finished";
  }
  return "unknown";
}

std::string status_json(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string text;
  const auto result = google::protobuf::util::MessageToJsonString(message, &text, options);
  if (!result.ok()) {
    // only for a message the board did not make valid; still JSON, still saying what went wrong
    status::Error error;
    error.set_status(500);
    error.set_error(valid_utf8("cannot print " + message.GetTypeName() + " as JSON: " + result.ToString()));
    text.clear();
    (void)google::protobuf::util::MessageToJsonString(error, &text, options);
  }
  return text + "\n";
}

StatusBoard::StatusBoard(std::filesystem::path run_dir, Clock clock)
    : run_dir_(std::move(run_dir)),
      clock_(clock ? std::move(clock) : Clock([] { return std::chrono::steady_clock::now(); })),
      created_(clock_()) {}

// ---------------------------------------------------------------------------------------------------------
// publishing

void StatusBoard::publish_run(const RunState& state, int last_checkpoint_iteration) {
  // the copy, outside the lock
  auto snapshot = std::make_shared<RunSnapshot>();
  snapshot->mode = state.settings.mode;
  snapshot->seed = state.settings.seed;
  snapshot->next_iteration = state.next_iteration;
  snapshot->iterations = state.settings.iterations;
  snapshot->finished = run_complete(state);
  snapshot->counters = state.counters;
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
    info.difficulty_level = static_cast<int>(difficulty(p.env.encoding));
    snapshot->pairs.push_back(std::move(info));
  }
  const RateSample sample{clock_(), state.counters.rollouts, state.counters.env_steps};

  // the swap, under it (the previous snapshot is freed after, outside it)
  std::shared_ptr<const RunSnapshot> previous;
  std::lock_guard lock(mutex_);
  previous = std::exchange(run_, std::move(snapshot));
  // counters that went back (a new state) start the window over
  if (!rate_samples_.empty() &&
      (sample.rollouts < rate_samples_.back().rollouts || sample.env_steps < rate_samples_.back().env_steps))
    rate_samples_.clear();
  rate_samples_.push_back(sample);
  while (rate_samples_.size() > kRateWindow) rate_samples_.pop_front();
}

void StatusBoard::publish_dispatch(DispatchSnapshot snapshot) {
  auto shared = std::make_shared<const DispatchSnapshot>(std::move(snapshot));
  const SteadyTime now = clock_();
  std::shared_ptr<const DispatchSnapshot> previous;  // freed after the lock is released
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

StatusBoard::View StatusBoard::view() const {
  std::lock_guard lock(mutex_);
  View v;
  v.run = run_;
  v.dispatch = dispatch_;
  v.dispatch_at = dispatch_at_;
  v.phase = phase_;
  v.note = note_;
  v.rollouts_per_s = rate(rate_samples_, [](const RateSample& s) { return s.rollouts; });
  v.env_steps_per_s = rate(rate_samples_, [](const RateSample& s) { return s.env_steps; });
  v.skipped_key_files = skipped_key_files_;
  return v;
}

// ---------------------------------------------------------------------------------------------------------
// reading

status::Status StatusBoard::status() const {
  const View v = view();
  status::Status s;
  s.set_run_dir(valid_utf8(run_dir_.string()));
  s.set_state(std::string(to_string(v.phase)));
  s.set_note(valid_utf8(v.note));
  s.set_uptime_s(std::chrono::duration<double>(clock_() - created_).count());
  s.set_rollouts_per_s(v.rollouts_per_s);
  s.set_env_steps_per_s(v.env_steps_per_s);
  if (v.run) {
    const RunSnapshot& run = *v.run;
    s.set_mode(std::string(mode_name(run.mode)));
    s.set_seed(run.seed);
    s.set_iteration(run.next_iteration);
    s.set_iterations(run.iterations);
    s.set_finished(run.finished);
    s.set_pairs_created(static_cast<int32_t>(run.pairs.size()));
    int active = 0, solved = 0;
    for (const PairInfo& info : run.pairs) {
      active += info.pair.active() ? 1 : 0;
      solved += info.pair.solved() ? 1 : 0;
    }
    s.set_pairs_active(active);
    s.set_pairs_solved(solved);
    s.set_rollouts(run.counters.rollouts);
    s.set_env_steps(run.counters.env_steps);
    s.set_transfer_attempts(run.counters.transfer_attempts);
    s.set_transfer_successes(run.counters.transfer_successes);
    s.set_last_checkpoint_iteration(run.last_checkpoint_iteration);
  }
  if (v.dispatch) {
    s.set_workers(static_cast<int32_t>(v.dispatch->workers.size()));
    s.set_queue_depth(v.dispatch->queue_depth);
    s.set_in_flight_jobs(v.dispatch->in_flight_jobs);
    for (const auto& [reason, count] : v.dispatch->dropped_frames)
      (*s.mutable_dropped_frames())[valid_utf8(reason)] = count;
  }
  return s;
}

status::PairSummary StatusBoard::summary(const PairInfo& info) const {
  const Pair& p = info.pair;
  status::PairSummary s;
  s.set_id(p.id);
  s.set_env(valid_utf8(p.env.encoding.name));
  s.set_seed(p.env.seed);
  *s.mutable_encoding() = to_proto(p.env.encoding);
  s.mutable_encoding()->set_name(valid_utf8(p.env.encoding.name));
  s.set_created_iteration(p.created_iteration);
  s.set_parent_id(p.parent_id);
  s.set_retired_iteration(p.retired_iteration);
  s.set_active(p.active());
  s.set_latest_score(p.latest_score);
  s.set_best_score(p.best_score);
  s.set_best_iteration(p.best_iteration);
  s.set_solved(p.solved());
  s.set_first_solved_iteration(p.first_solved_iteration);
  s.set_es_steps(p.es_steps);
  s.set_difficulty(std::string(to_string(static_cast<Difficulty>(info.difficulty_level))));
  s.set_difficulty_level(info.difficulty_level);
  return s;
}

status::PairList StatusBoard::pairs() const {
  const View v = view();
  status::PairList list;
  if (!v.run) return list;
  for (const PairInfo& info : v.run->pairs) *list.add_pairs() = summary(info);
  return list;
}

bool StatusBoard::has_pair(int id) const {
  const View v = view();
  return v.run && std::any_of(v.run->pairs.begin(), v.run->pairs.end(),
                              [id](const PairInfo& info) { return info.pair.id == id; });
}

std::optional<status::PairDetail> StatusBoard::pair(int id) const {
  const View v = view();
  if (!v.run) return std::nullopt;
  const auto& all = v.run->pairs;
  std::unordered_map<int, const PairInfo*> by_id;
  for (const PairInfo& info : all) by_id[info.pair.id] = &info;
  const auto found = by_id.find(id);
  if (found == by_id.end()) return std::nullopt;
  const Pair& p = found->second->pair;

  status::PairDetail detail;
  *detail.mutable_pair() = summary(*found->second);
  for (const ScoreRow& row : scores_of(id)) {
    status::ScorePoint* point = detail.add_scores();
    point->set_iteration(row.iteration);
    point->set_score(row.score);
    point->set_best_score(row.best_score);
  }

  // lineage: the parent chain (bounded by the number of pairs, whatever the ids say), the first θ, transfers
  status::Lineage* lineage = detail.mutable_lineage();
  for (int parent = p.parent_id; parent != kNone && lineage->ancestors_size() < static_cast<int>(all.size());) {
    lineage->add_ancestors(parent);
    const auto next = by_id.find(parent);
    parent = next == by_id.end() ? kNone : next->second->pair.parent_id;
  }
  lineage->set_initial_source_pair(p.initial_source_pair);
  lineage->set_initial_by_proposal(p.initial_by_proposal);
  lineage->set_admission_score(p.admission_score);
  for (const TransferRecord& t : p.transfers) {
    status::Transfer* transfer = lineage->add_transfers();
    transfer->set_iteration(t.iteration);
    transfer->set_source_pair(t.source_pair);
    transfer->set_proposal(t.proposal);
    transfer->set_score(t.score);
  }
  lineage->set_transfer_attempts(p.transfer_attempts);
  return detail;
}

status::Archive StatusBoard::archive() const {
  const View v = view();
  status::Archive archive;
  if (!v.run) return archive;
  for (const PairInfo& info : v.run->pairs) {
    const Pair& p = info.pair;
    status::ArchiveEntry* entry = archive.add_pairs();
    entry->set_id(p.id);
    entry->set_env(valid_utf8(p.env.encoding.name));
    entry->set_seed(p.env.seed);
    *entry->mutable_encoding() = to_proto(p.env.encoding);
    entry->mutable_encoding()->set_name(valid_utf8(p.env.encoding.name));
    entry->set_active(p.active());
  }
  return archive;
}

status::WorkerList StatusBoard::workers() const {
  const View v = view();
  status::WorkerList list;
  if (!v.dispatch) return list;
  const double age = std::max(0.0, std::chrono::duration<double>(clock_() - v.dispatch_at).count());
  for (const WorkerSnapshot& w : v.dispatch->workers) {
    status::Worker* worker = list.add_workers();
    worker->set_id(peer_id_text(w.id));
    worker->set_address(valid_utf8(w.address));
    worker->set_threads(w.threads);
    worker->set_jobs_done(w.jobs_done);
    worker->set_results_done(w.results_done);
    worker->set_seconds_since_heartbeat(w.seconds_since_heartbeat + age);
    worker->set_fingerprint_digest(hex_text(w.fingerprint_digest));
  }
  list.set_queue_depth(v.dispatch->queue_depth);
  list.set_in_flight_jobs(v.dispatch->in_flight_jobs);
  for (const auto& [reason, count] : v.dispatch->dropped_frames)
    (*list.mutable_dropped_frames())[valid_utf8(reason)] = count;
  return list;
}

Expected<status::EventList> StatusBoard::events(int64_t since, int64_t limit) const {
  limit = std::clamp<int64_t>(limit, 1, kMaxEventsPerPage);
  since = std::max<int64_t>(since, 0);
  status::EventList list;
  list.set_since(since);
  list.set_next(since);

  const std::filesystem::path path = run_dir_ / kEventsFile;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return list;  // no events yet
    return Unexpected{path.string() + ": cannot read"};
  }
  std::string line;
  int64_t index = 0;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // a last line without its newline is still being written
    if (index++ < since) continue;
    if (list.events_size() == limit) {
      list.set_more(true);
      break;
    }
    google::protobuf::Struct* event = list.add_events();
    if (!google::protobuf::util::JsonStringToMessage(line, event).ok()) {
      event->Clear();
      (*event->mutable_fields())["unparsed"].set_string_value(valid_utf8(line));
    }
  }
  if (in.bad()) return Unexpected{path.string() + ": read error"};
  list.set_next(since + list.events_size());
  return list;
}

std::string StatusBoard::metrics_text() const {
  const View v = view();
  std::string text;
  auto family = [&](const char* name, const char* type, const char* help) {
    text += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
  };
  auto sample = [&](const std::string& name, auto value) { text += name + " " + std::to_string(value) + "\n"; };

  const RunSnapshot empty;
  const RunSnapshot& run = v.run ? *v.run : empty;
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

  const DispatchSnapshot no_dispatch;
  const DispatchSnapshot& dispatch = v.dispatch ? *v.dispatch : no_dispatch;
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
      {"poet_verified_jobs_total", "counter", "Jobs run on two workers whose results matched bit for bit.",
       dispatch.verified_jobs},
      {"poet_unverified_jobs_total", "counter",
       "Jobs chosen for verification that no other worker was connected to check.", dispatch.unverified_jobs},
      {"poet_wrong_workers_total", "counter",
       "Workers refused because their results differed from two other workers'.", dispatch.wrong_workers},
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

  family("poet_uptime_seconds", "gauge", "Seconds since the coordinator started.");
  char uptime[32];
  std::snprintf(uptime, sizeof uptime, "%.3f", std::chrono::duration<double>(clock_() - created_).count());
  text += std::string("poet_uptime_seconds ") + uptime + "\n";
  return text;
}

// ---------------------------------------------------------------------------------------------------------
// pair_stats.csv

std::vector<StatusBoard::ScoreRow> StatusBoard::scores_of(int id) const {
  std::lock_guard lock(stats_mutex_);
  read_stats();
  const auto found = stats_.rows.find(id);
  return found == stats_.rows.end() ? std::vector<ScoreRow>{} : found->second;
}

void StatusBoard::read_stats() const {
  const std::filesystem::path path = run_dir_ / kStatsFile;
  std::ifstream in(path, std::ios::binary);
  if (!in) return;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return;
  if (static_cast<uint64_t>(size) < stats_.offset) stats_ = StatsCache{};  // the file was cut back: start over
  in.seekg(static_cast<std::streamoff>(stats_.offset));

  // read on in blocks; only whole lines are consumed, a partial last one is read again next time
  std::string pending;
  std::vector<char> block(1 << 20);
  while (in.read(block.data(), static_cast<std::streamsize>(block.size())) || in.gcount() > 0) {
    pending.append(block.data(), static_cast<size_t>(in.gcount()));
    size_t start = 0;
    for (size_t newline; (newline = pending.find('\n', start)) != std::string::npos; start = newline + 1) {
      read_stats_line(std::string_view(pending).substr(start, newline - start));
      stats_.offset += newline + 1 - start;
    }
    pending.erase(0, start);
  }
}

void StatusBoard::read_stats_line(std::string_view line) const {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  const std::vector<std::string> fields = csv_fields(line);
  if (stats_.iteration_column < 0) {  // the header names the columns
    for (int i = 0; i < static_cast<int>(fields.size()); ++i) {
      if (fields[i] == "iteration") stats_.iteration_column = i;
      if (fields[i] == "pair") stats_.pair_column = i;
      if (fields[i] == "score") stats_.score_column = i;
      if (fields[i] == "best_score") stats_.best_column = i;
    }
    return;
  }
  const int needed = std::max({stats_.iteration_column, stats_.pair_column, stats_.score_column, stats_.best_column});
  if (needed < 0 || static_cast<int>(fields.size()) <= needed) return;
  ScoreRow row;
  int pair = 0;
  if (parse_field(fields[stats_.iteration_column], row.iteration) && parse_field(fields[stats_.pair_column], pair) &&
      parse_field(fields[stats_.score_column], row.score) && parse_field(fields[stats_.best_column], row.best_score))
    stats_.rows[pair].push_back(row);
}

}  // namespace poet
