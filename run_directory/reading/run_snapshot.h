#pragma once
// A run directory as the analysis tools see it: the state of its checkpoint and the log lines that state has
// seen, read without changing anything (no file written or truncated; run.lock is only probed). The checkpoint is
// replaced atomically and records the logs' sizes, so a run being written while it is read gives the
// consistent picture of its last checkpoint; the lines a live run appended after it are left out.

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/plumbing/expected.h"
#include "common/plumbing/text_file.h"  // is_inside: the analysis tools write nothing in the run directory
#include "engine/run_state.h"
#include "poet.pb.h"
#include "run_directory/files/wall_times.h"
#include "run_directory/reading/pair_stats_log.h"

namespace poet {

struct RunSnapshot {
  std::filesystem::path dir;
  RunState state;
  pb::RunConfig config;                // the checkpoint's config
  std::string config_text;             // the same in text format (what config.textproto holds)
  std::vector<nlohmann::json> events;  // events.jsonl up to the checkpoint's size, one object per line
  std::vector<StatsRow> stats;         // pair_stats.csv up to the checkpoint's size
  std::string stats_text;              // the same bytes, checked (size and CRC-32), for readers of every column
  bool live = false;                   // another process holds run.lock: the run is being written
  // wall_times.csv up to the checkpoint's iteration; empty when the run has none. The file is a record of the
  // machine, not of the run, so damage to it is reported here rather than refusing the run.
  std::vector<WallTime> wall_times;
  std::string wall_times_problem;
};

// Reads dir. Errors name the file and say what is wrong: a missing directory or file, a damaged or truncated
// checkpoint or log, a checkpoint of a newer format than this build reads.
Expected<RunSnapshot> read_run_snapshot(const std::filesystem::path& dir);

}  // namespace poet
