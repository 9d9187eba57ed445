#include "coordinator/status/status_messages.h"

#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <unordered_map>

#include "common/formats/envgen/env_proto.h"
#include "common/text/text_format.h"
#include "common/text/utf8.h"
#include "coordinator/status/status_board.h"
#include "run_directory/reading/events_log.h"
#include "simulation/envgen/env_distance.h"

namespace poet {
namespace {

status::PairSummary summary(const PairInfo& info) {
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
  s.set_difficulty(std::string(level_label(p.env.encoding)));
  s.set_difficulty_level(info.difficulty_level);
  return s;
}

void copy_measures(const ObstacleMeasures& m, status::ObstacleMeasures& out) {
  out.set_roughness(m[0]);
  out.set_gap_hi(m[1]);
  out.set_stump_hi(m[2]);
}

template <class Map>
void copy_dropped_frames(const DispatchView& dispatch, Map& out) {
  for (const auto& [reason, count] : dispatch.dropped_frames) out[valid_utf8(reason)] = count;
}

}  // namespace

status::Status status_message(const BoardView& v, const std::filesystem::path& run_dir) {
  status::Status s;
  s.set_run_dir(valid_utf8(run_dir.string()));
  s.set_state(std::string(to_string(v.phase)));
  s.set_note(valid_utf8(v.note));
  s.set_uptime_s(v.uptime_s);
  s.set_rollouts_per_s(v.rollouts_per_s);
  s.set_env_steps_per_s(v.env_steps_per_s);
  if (v.run) {
    const PublishedRun& run = *v.run;
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
    s.set_annecs_at_admission(run.annecs.at_admission);
    s.set_annecs_at_archiving(run.annecs.at_archiving);
    s.set_last_checkpoint_iteration(run.last_checkpoint_iteration);
    copy_measures(run.frontier_solved, *s.mutable_frontier_solved());
    copy_measures(run.frontier_admitted, *s.mutable_frontier_admitted());
    if (run.highest_level_solved >= 0)
      s.set_highest_level_solved(std::string(to_string(static_cast<Difficulty>(run.highest_level_solved))));
  }
  if (v.dispatch) {
    s.set_workers(static_cast<int32_t>(v.dispatch->workers.size()));
    s.set_queue_depth(v.dispatch->queue_depth);
    s.set_in_flight_jobs(v.dispatch->in_flight_jobs);
    copy_dropped_frames(*v.dispatch, *s.mutable_dropped_frames());
  }
  return s;
}

status::PairList pair_list(const BoardView& v) {
  status::PairList list;
  if (!v.run) return list;
  for (const PairInfo& info : v.run->pairs) *list.add_pairs() = summary(info);
  return list;
}

std::optional<status::PairDetail> pair_detail(const BoardView& v, int id, const std::vector<StatsRow>& scores) {
  if (!v.run) return std::nullopt;
  const auto& all = v.run->pairs;
  std::unordered_map<int, const PairInfo*> by_id;
  for (const PairInfo& info : all) by_id[info.pair.id] = &info;
  const auto found = by_id.find(id);
  if (found == by_id.end()) return std::nullopt;
  const Pair& p = found->second->pair;

  status::PairDetail detail;
  *detail.mutable_pair() = summary(*found->second);
  for (const StatsRow& row : scores) {
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

status::Archive archive_message(const BoardView& v) {
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

namespace {

void fill_worker(const WorkerView& w, const BoardView& v, status::Worker& worker) {
  worker.set_id(peer_id_text(w.id));
  worker.set_address(valid_utf8(w.name));
  worker.set_threads(w.threads);
  worker.set_jobs_done(w.jobs_done);
  worker.set_results_done(w.results_done);
  worker.set_seconds_since_heartbeat(static_cast<double>(v.dispatch->at - w.last_heard) / 1000 + v.dispatch_age_s);
  worker.set_fingerprint_digest(hex_text(w.fingerprint_digest));
  worker.set_arithmetic_digest(hex_text(w.arithmetic_digest));
  worker.set_trust(name(w.trust));
  worker.set_checks_passed(w.checks_passed);
  worker.set_answers_taken(w.answers_taken);
  worker.set_answers_taken_unchecked(w.answers_taken_unchecked);
  worker.set_probation_answers(w.probation_answers);
}

}  // namespace

status::WorkerList worker_list(const BoardView& v) {
  status::WorkerList list;
  if (!v.dispatch) return list;
  for (const WorkerView& w : v.dispatch->workers) fill_worker(w, v, *list.add_workers());
  for (const WorkerView& w : v.dispatch->refused) fill_worker(w, v, *list.add_refused());
  list.set_queue_depth(v.dispatch->queue_depth);
  list.set_in_flight_jobs(v.dispatch->in_flight_jobs);
  copy_dropped_frames(*v.dispatch, *list.mutable_dropped_frames());
  return list;
}

Expected<status::EventList> event_list(const std::filesystem::path& events_file, int64_t since, int64_t limit) {
  status::EventList list;
  list.set_since(since);
  list.set_next(since);
  Expected<EventLinesPage> page = read_event_lines(events_file, since, limit);
  if (!page) return Unexpected{page.error()};
  for (const std::string& line : page->lines) {
    google::protobuf::Struct* event = list.add_events();
    if (!google::protobuf::util::JsonStringToMessage(line, event).ok()) {
      event->Clear();
      (*event->mutable_fields())["unparsed"].set_string_value(valid_utf8(line));
    }
  }
  list.set_more(page->more);
  list.set_next(since + list.events_size());
  return list;
}

}  // namespace poet
