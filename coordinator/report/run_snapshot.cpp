#include "report/run_snapshot.h"

#include <fstream>
#include <map>
#include <optional>

#include "csv_fields.h"
#include "run/checkpoint.h"
#include "run/checkpoint_file.h"
#include "run/crc32.h"
#include "run/run_directory.h"
#include "run/run_lock.h"

namespace poet {
namespace fs = std::filesystem;
namespace {

// The first `size` bytes of a log, or an error when the file is missing or shorter (the checkpoint was written
// after the logs were made durable, so a shorter log was damaged after the fact) or, when the checkpoint has their
// CRC-32 (`crc`), they differ from what it saw.
Expected<std::string> read_log_prefix(const fs::path& path, int64_t size, std::optional<uint32_t> crc) {
  std::error_code ec;
  const std::uintmax_t present = fs::file_size(path, ec);
  if (ec) return Unexpected{path.string() + ": cannot read (" + ec.message() + "); the run directory is incomplete"};
  if (size < 0 || present < static_cast<std::uintmax_t>(size))
    return Unexpected{path.string() + ": " + std::to_string(present) + " bytes, but the checkpoint records " +
                      std::to_string(size) + " (the file was truncated or damaged)"};
  std::ifstream in(path, std::ios::binary);
  std::string bytes(static_cast<size_t>(size), '\0');
  if (!in.read(bytes.data(), size)) return Unexpected{path.string() + ": cannot read"};
  if (crc && crc32_extend(0, bytes) != *crc) return Unexpected{log_changed_error(path, size)};
  return bytes;
}

// Splits whole lines; a last line without its newline is damage (the writer appends whole lines).
Expected<std::vector<std::string_view>> lines_of(const fs::path& path, std::string_view bytes) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  for (size_t newline; (newline = bytes.find('\n', start)) != std::string_view::npos; start = newline + 1)
    lines.push_back(bytes.substr(start, newline - start));
  if (start != bytes.size()) return Unexpected{path.string() + ": the last line recorded by the checkpoint is cut"};
  return lines;
}

Expected<std::vector<nlohmann::json>> parse_events(const fs::path& path, std::string_view bytes) {
  Expected<std::vector<std::string_view>> lines = lines_of(path, bytes);
  if (!lines) return Unexpected{lines.error()};
  std::vector<nlohmann::json> events;
  for (size_t i = 0; i < lines->size(); ++i) {
    nlohmann::json event = nlohmann::json::parse((*lines)[i], nullptr, false);
    if (event.is_discarded() || !event.is_object() || !event.contains("iteration") || !event.contains("event") ||
        !event["iteration"].is_number_integer() || !event["event"].is_string())
      return Unexpected{path.string() + ":" + std::to_string(i + 1) +
                        ": not an event (a JSON object with \"iteration\" and \"event\")"};
    events.push_back(std::move(event));
  }
  return events;
}

Expected<std::vector<StatsRow>> parse_stats(const fs::path& path, std::string_view bytes) {
  Expected<std::vector<std::string_view>> lines = lines_of(path, bytes);
  if (!lines) return Unexpected{lines.error()};
  if (lines->empty()) return Unexpected{path.string() + ": no header line"};
  std::map<std::string, size_t> column;
  const std::vector<std::string> header = csv_fields((*lines)[0]);
  for (size_t i = 0; i < header.size(); ++i) column[header[i]] = i;
  for (const char* required : {"iteration", "pair", "score", "finished", "best_score", "solved", "es_steps"})
    if (!column.count(required)) return Unexpected{path.string() + ": the header has no column \"" + required + "\""};
  const auto optional_column = [&](const char* name) { return column.count(name) ? column[name] : header.size(); };
  const size_t rollouts_column = optional_column("run_rollouts");
  const size_t env_steps_column = optional_column("run_env_steps");

  std::vector<StatsRow> rows;
  for (size_t n = 1; n < lines->size(); ++n) {
    const std::vector<std::string> f = csv_fields((*lines)[n]);
    const auto bad = [&](const char* name) {
      return Unexpected{path.string() + ":" + std::to_string(n + 1) + ": " + name + ": not a valid value"};
    };
    if (f.size() != header.size())
      return Unexpected{path.string() + ":" + std::to_string(n + 1) + ": " + std::to_string(f.size()) +
                        " fields, the header has " + std::to_string(header.size())};
    StatsRow row;
    if (!parse_field(f[column["iteration"]], row.iteration)) return bad("iteration");
    if (!parse_field(f[column["pair"]], row.pair)) return bad("pair");
    if (!parse_field(f[column["score"]], row.score)) return bad("score");
    if (!parse_field(f[column["best_score"]], row.best_score)) return bad("best_score");
    if (!parse_field(f[column["es_steps"]], row.es_steps)) return bad("es_steps");
    row.finished = f[column["finished"]] == "true";
    row.solved = f[column["solved"]] == "true";
    if (rollouts_column < f.size() && !parse_field(f[rollouts_column], row.run_rollouts)) return bad("run_rollouts");
    if (env_steps_column < f.size() && !parse_field(f[env_steps_column], row.run_env_steps))
      return bad("run_env_steps");
    rows.push_back(row);
  }
  return rows;
}

// wall_times.csv's lines of the iterations the checkpoint has seen.
void load_wall_times(RunSnapshot& snapshot) {
  const fs::path path = snapshot.dir / kWallTimesFile;
  std::error_code ec;
  if (!fs::exists(path, ec)) return;
  Expected<std::vector<WallTime>> lines = read_wall_times(path);
  if (!lines) {
    snapshot.wall_times_problem = path.string() + ": " + lines.error();
    return;
  }
  for (const WallTime& w : *lines)
    if (w.iteration < snapshot.state.next_iteration) snapshot.wall_times.push_back(w);
}

}  // namespace

bool is_inside(const fs::path& path, const fs::path& dir) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
  const fs::path d = fs::weakly_canonical(fs::absolute(dir), ec);
  auto pi = p.begin();
  for (auto di = d.begin(); di != d.end(); ++di, ++pi) {
    if (di->empty()) continue;  // a trailing separator
    if (pi == p.end() || *pi != *di) return false;
  }
  return true;
}

Expected<RunSnapshot> read_run_snapshot(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return Unexpected{dir.string() + ": no such directory"};
  const fs::path checkpoint_path = dir / kCheckpointFile;
  if (!fs::exists(checkpoint_path, ec)) {
    const bool started = fs::exists(dir / kConfigFile, ec);
    return Unexpected{
        checkpoint_path.string() + ": does not exist (" + dir.string() +
        (started ? " holds a run that has not saved its first checkpoint yet)" : " is not a run directory)")};
  }
  Expected<pb::Checkpoint> checkpoint = read_checkpoint_file(checkpoint_path);
  if (!checkpoint) return Unexpected{checkpoint.error()};
  if (!checkpoint->has_events_bytes() || !checkpoint->has_stats_bytes())
    return Unexpected{checkpoint_path.string() + ": no log sizes recorded (not a run directory's checkpoint)"};
  Expected<RunState> state = from_checkpoint(*checkpoint);
  if (!state) return Unexpected{checkpoint_path.string() + ": " + state.error()};

  RunSnapshot snapshot;
  snapshot.dir = dir;
  snapshot.state = std::move(*state);
  snapshot.live = RunLock::held_by_another_process(dir);

  const fs::path events_path = dir / kEventsFile;
  Expected<std::string> events = read_log_prefix(events_path, checkpoint->events_bytes(),
                                                    checkpoint->has_events_crc32()
                                                        ? std::optional<uint32_t>(checkpoint->events_crc32())
                                                        : std::nullopt);
  if (!events) return Unexpected{events.error()};
  Expected<std::vector<nlohmann::json>> parsed_events = parse_events(events_path, *events);
  if (!parsed_events) return Unexpected{parsed_events.error()};
  snapshot.events = std::move(*parsed_events);

  const fs::path stats_path = dir / kStatsFile;
  Expected<std::string> stats = read_log_prefix(stats_path, checkpoint->stats_bytes(),
                                                  checkpoint->has_stats_crc32()
                                                      ? std::optional<uint32_t>(checkpoint->stats_crc32())
                                                      : std::nullopt);
  if (!stats) return Unexpected{stats.error()};
  Expected<std::vector<StatsRow>> rows = parse_stats(stats_path, *stats);
  if (!rows) return Unexpected{rows.error()};
  snapshot.stats = std::move(*rows);
  load_wall_times(snapshot);
  return snapshot;
}

}  // namespace poet
