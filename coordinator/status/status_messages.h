#pragma once
// A board view as the status socket's JSON messages (proto/status.proto): what /status, /pairs, /pairs/{id},
// /archive, /workers and /events answer. Names and paths are made valid UTF-8 on the way (protobuf's JSON printer
// refuses anything else).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/plumbing/expected.h"
#include "coordinator/status/board_view.h"
#include "run_directory/reading/pair_stats_log.h"
#include "status.pb.h"

namespace poet {

status::Status status_message(const BoardView& view, const std::filesystem::path& run_dir);
status::PairList pair_list(const BoardView& view);
// The pair with its lineage and `scores` (its rows of pair_stats.csv); nullopt for an id the run has not.
std::optional<status::PairDetail> pair_detail(const BoardView& view, int id, const std::vector<StatsRow>& scores);
status::Archive archive_message(const BoardView& view);
// Heartbeat ages are the published ones plus the view's dispatch_age_s.
status::WorkerList worker_list(const BoardView& view);
// A page of events.jsonl's lines (run_directory/reading/events_log.h), each line that is not a JSON object shown as
// {"unparsed": line}.
Expected<status::EventList> event_list(const std::filesystem::path& events_file, int64_t since, int64_t limit);

}  // namespace poet
