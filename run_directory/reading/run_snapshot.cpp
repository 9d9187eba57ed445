#include "run_directory/reading/run_snapshot.h"

#include <optional>

#include "common/plumbing/text_file.h"
#include "run_directory/config/run_config.h"
#include "run_directory/files/checkpoint.h"
#include "run_directory/files/checkpoint_file.h"
#include "run_directory/files/log_prefix.h"
#include "run_directory/files/run_directory.h"
#include "run_directory/files/run_lock.h"
#include "run_directory/reading/events_log.h"

namespace poet {
namespace fs = std::filesystem;
namespace {

// wall_times.csv's lines of the iterations the checkpoint has seen.
void load_wall_times(RunSnapshot& snapshot) {
  const fs::path path = snapshot.dir / kWallTimesFile;
  Expected<std::vector<WallTime>> lines = read_wall_times(path);
  if (!lines) {
    if (lines.error() != kDoesNotExist) snapshot.wall_times_problem = path.string() + ": " + lines.error();
    return;  // no file: no times, and nothing wrong
  }
  for (const WallTime& w : *lines)
    if (w.iteration < snapshot.state.next_iteration) snapshot.wall_times.push_back(w);
}

}  // namespace

Expected<RunSnapshot> read_run_snapshot(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return Unexpected{dir.string() + ": no such directory"};
  const fs::path checkpoint_path = dir / kCheckpointFile;
  Expected<pb::Checkpoint> checkpoint = read_checkpoint_file(checkpoint_path);
  if (!checkpoint && checkpoint.error() == checkpoint_path.string() + ": " + kDoesNotExist) {
    const bool started = fs::exists(dir / kConfigFile, ec);
    return Unexpected{
        checkpoint.error() + " (" + dir.string() +
        (started ? " holds a run that has not saved its first checkpoint yet)" : " is not a run directory)")};
  }
  if (!checkpoint) return Unexpected{checkpoint.error()};
  if (!checkpoint->has_events_bytes() || !checkpoint->has_stats_bytes())
    return Unexpected{checkpoint_path.string() + ": no log sizes recorded (not a run directory's checkpoint)"};
  Expected<RunState> state = from_checkpoint(*checkpoint);
  if (!state) return Unexpected{checkpoint_path.string() + ": " + state.error()};

  RunSnapshot snapshot;
  snapshot.dir = dir;
  snapshot.state = std::move(*state);
  snapshot.config = checkpoint->config();
  snapshot.config_text = run_config_text(snapshot.config);
  snapshot.live = RunLock::held_by_another_process(dir);

  const fs::path events_path = dir / kEventsFile;
  Expected<std::string> events = read_log_prefix(
      events_path, checkpoint->events_bytes(),
      checkpoint->has_events_crc32() ? std::optional<uint32_t>(checkpoint->events_crc32()) : std::nullopt);
  if (!events) return Unexpected{events.error()};
  Expected<std::vector<nlohmann::json>> parsed_events = parse_events(events_path, *events);
  if (!parsed_events) return Unexpected{parsed_events.error()};
  snapshot.events = std::move(*parsed_events);

  const fs::path stats_path = dir / kStatsFile;
  Expected<std::string> stats = read_log_prefix(
      stats_path, checkpoint->stats_bytes(),
      checkpoint->has_stats_crc32() ? std::optional<uint32_t>(checkpoint->stats_crc32()) : std::nullopt);
  if (!stats) return Unexpected{stats.error()};
  Expected<std::vector<StatsRow>> rows = parse_stats(stats_path, *stats);
  if (!rows) return Unexpected{rows.error()};
  snapshot.stats = std::move(*rows);
  snapshot.stats_text = std::move(*stats);
  load_wall_times(snapshot);
  return snapshot;
}

}  // namespace poet
