#include "run_directory/files/run_directory.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <exception>
#include <new>
#include <string_view>
#include <system_error>
#include <tuple>

#include "common/formats/envgen/env_json.h"
#include "common/formats/policy/policy_file.h"
#include "common/plumbing/text_file.h"
#include "common/program/command_line.h"
#include "common/text/text_format.h"
#include "run_directory/config/run_config.h"
#include "run_directory/files/annecs_log.h"
#include "run_directory/files/checkpoint.h"
#include "run_directory/files/crc32.h"
#include "run_directory/files/event_json.h"

namespace poet {
namespace {

namespace fs = std::filesystem;

std::string errno_text(int err) { return std::generic_category().message(err); }

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

Expected<int> open_log(const fs::path& path, int extra_flags) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC | extra_flags, 0644);
  if (fd < 0) return Unexpected{path.string() + ": cannot open: " + errno_text(errno)};
  return fd;
}

Expected<int64_t> file_size(int fd, const fs::path& path) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) return Unexpected{path.string() + ": cannot stat: " + errno_text(errno)};
  return static_cast<int64_t>(st.st_size);
}

// Cuts a log back to the size a checkpoint recorded; a log shorter than that lost lines the state has seen.
std::optional<std::string> truncate_log(int fd, const fs::path& path, int64_t size) {
  Expected<int64_t> current = file_size(fd, path);
  if (!current) return current.error();
  if (*current < size)
    return path.string() + ": " + std::to_string(*current) + " bytes, shorter than the " + std::to_string(size) +
           " the checkpoint has seen (the file was changed outside the run)";
  if (*current == size) return std::nullopt;
  if (::ftruncate(fd, size) != 0) return path.string() + ": cannot truncate: " + errno_text(errno);
  if (const int err = fsync_retrying(fd)) return path.string() + ": fsync: " + errno_text(err);
  return std::nullopt;
}

std::optional<std::string> write_named(const fs::path& path, std::string_view text) {
  if (auto error = write_file_atomically(path, text)) return path.string() + ": " + *error;
  return std::nullopt;
}

std::string pair_file(int id, const char* suffix) { return "pair-" + std::to_string(id) + suffix; }

// True when path holds exactly text (a file that cannot be read counts as different).
bool same_content(const fs::path& path, const std::string& text) {
  Expected<std::string> current = read_text_file(path, text.size());
  return current && *current == text;
}

// Removes "<name>.tmp.<pid>.<n>" files that write_file_atomically leaves when its process dies mid-write. Only
// the lock's holder calls this, so no other writer's temporary can be in flight.
void remove_temporaries(const fs::path& dir) {
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".tmp.") != std::string::npos && entry.is_regular_file(ec)) fs::remove(entry.path(), ec);
  }
}

// Fails, naming the directory, when no file can be made in it (read-only, immutable, no space for an inode):
// found before any work is done rather than at the first checkpoint.
std::optional<std::string> probe_writable(const fs::path& dir) {
  const fs::path probe = dir / ("write-probe.tmp." + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd < 0) return dir.string() + ": cannot write files in it: " + errno_text(errno);
  ::close(fd);
  ::unlink(probe.c_str());
  return std::nullopt;
}

size_t files_in(const fs::path& dir) {
  std::error_code ec;
  size_t n = 0;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) n += 1;
  return n;
}

// What an earlier run left in dir, which holds no checkpoint: its logs' lines and its pair files. Empty for a
// fresh directory, and for one where a start was interrupted before its first checkpoint (config and headers).
std::vector<std::string> earlier_run_files(const fs::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  const std::uintmax_t events = fs::file_size(dir / kEventsFile, ec);
  if (!ec && events > 0) found.push_back(std::string(kEventsFile) + " (" + std::to_string(events) + " bytes)");
  const std::uintmax_t stats = fs::file_size(dir / kStatsFile, ec);
  if (!ec && stats > pair_stats_header().size())
    found.push_back(std::string(kStatsFile) + " (" + std::to_string(stats) + " bytes)");
  const std::uintmax_t annecs = fs::file_size(dir / kAnnecsFile, ec);
  if (!ec && annecs > annecs_header().size())
    found.push_back(std::string(kAnnecsFile) + " (" + std::to_string(annecs) + " bytes)");
  for (const char* sub : {kEnvsDir, kPoliciesDir})
    if (const size_t n = files_in(dir / sub); n > 0)
      found.push_back(std::string(sub) + "/ (" + std::to_string(n) + " files)");
  return found;
}

std::string joined(const std::vector<std::string>& parts) {
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : ", ") + part;
  return text;
}

// The CRC-32 of a log's first `size` bytes, checked against the checkpoint's when it has one.
Expected<uint32_t> checked_log_crc(const fs::path& path, int64_t size, bool recorded, uint32_t expected) {
  Expected<uint32_t> crc = file_prefix_crc32(path, size);
  if (!crc) return crc;
  if (recorded && *crc != expected) return Unexpected{log_changed_error(path, size)};
  return crc;
}

pb::Checkpoint checkpoint_with_logs(const pb::RunConfig& config, const RunState& state, const int64_t (&bytes)[2],
                                    const uint32_t (&crcs)[2]) {
  pb::Checkpoint checkpoint = to_checkpoint(config, state);
  checkpoint.set_events_bytes(bytes[0]);
  checkpoint.set_stats_bytes(bytes[1]);
  checkpoint.set_events_crc32(crcs[0]);
  checkpoint.set_stats_crc32(crcs[1]);
  checkpoint.set_written_by(project_version());
  return checkpoint;
}

}  // namespace

std::string log_changed_error(const fs::path& path, int64_t size) {
  return path.string() + ": its first " + std::to_string(size) +
         " bytes differ from those the checkpoint has seen (CRC-32 mismatch: the file was changed outside the "
         "run); restore it from a backup, or recompute the run from its config in another directory (runs are "
         "deterministic)";
}

std::string pair_stats_header() {
  return "iteration,pair,env,score,finished,eval_steps,best_score,solved,es_steps,lr,sigma,perturbation_mean,"
         "perturbation_max,grad_norm,theta_norm,run_rollouts,run_env_steps,pair_env_steps\n";
}

std::string pair_stats_row(const PairStatsRow& row) {
  std::string line = std::to_string(row.iteration) + "," + std::to_string(row.pair) + "," + csv_field(row.env);
  line += "," + number_text(row.score) + "," + (row.finished ? "true" : "false") + "," + std::to_string(row.eval_steps);
  line +=
      "," + number_text(row.best_score) + "," + (row.solved ? "true" : "false") + "," + std::to_string(row.es_steps);
  line += "," + number_text(row.lr) + "," + number_text(row.sigma) + "," + number_text(row.perturbation_mean);
  line +=
      "," + number_text(row.perturbation_max) + "," + number_text(row.grad_norm) + "," + number_text(row.theta_norm);
  line += "," + std::to_string(row.run_rollouts) + "," + std::to_string(row.run_env_steps) + "," +
          std::to_string(row.pair_env_steps) + "\n";
  return line;
}

RunDirectory::RunDirectory(fs::path dir, RunLock lock) : dir_(std::move(dir)), lock_(std::move(lock)) {}

Expected<RunDirectory> RunDirectory::create(const fs::path& dir, const pb::RunConfig& config) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Unexpected{dir.string() + ": cannot create directory: " + ec.message()};
  if (!fs::is_directory(dir, ec)) return Unexpected{dir.string() + ": not a directory"};
  Expected<RunLock> lock = RunLock::acquire(dir);
  if (!lock) return Unexpected{lock.error()};
  const Expected<bool> has_checkpoint = path_exists(dir / kCheckpointFile);
  if (!has_checkpoint) return Unexpected{(dir / kCheckpointFile).string() + ": " + has_checkpoint.error()};
  if (*has_checkpoint) return Unexpected{dir.string() + " already holds a run; resume it or choose another directory"};
  if (const std::vector<std::string> earlier = earlier_run_files(dir); !earlier.empty())
    return Unexpected{dir.string() + " holds files of an earlier run but no " + kCheckpointFile + ": " +
                      joined(earlier) +
                      ". Without its checkpoint that run cannot be resumed, and a new run here "
                      "would overwrite them: move them away (or remove them) to start a new run in this directory, "
                      "or choose another one"};
  for (const char* sub : {kEnvsDir, kPoliciesDir}) {
    fs::create_directories(dir / sub, ec);
    if (ec) return Unexpected{(dir / sub).string() + ": cannot create directory: " + ec.message()};
    if (auto error = probe_writable(dir / sub)) return Unexpected{*error};
  }
  if (auto error = write_named(dir / kConfigFile, run_config_text(config))) return Unexpected{*error};

  // A directory without a checkpoint holds no run, so logs left by an earlier attempt are started over.
  RunDirectory run(dir, std::move(*lock));
  run.config_ = config;
  Expected<int> events = open_log(dir / kEventsFile, O_CREAT | O_TRUNC);
  if (!events) return Unexpected{events.error()};
  run.events_fd_ = UniqueFd(*events);
  Expected<int> stats = open_log(dir / kStatsFile, O_CREAT | O_TRUNC);
  if (!stats) return Unexpected{stats.error()};
  run.stats_fd_ = UniqueFd(*stats);
  if (const int err = write_all(run.stats_fd_.get(), pair_stats_header()))
    return Unexpected{(dir / kStatsFile).string() + ": " + errno_text(err)};
  run.stats_crc_ = crc32_extend(0, pair_stats_header());
  Expected<int> annecs = open_log(dir / kAnnecsFile, O_CREAT | O_TRUNC);
  if (!annecs) return Unexpected{annecs.error()};
  run.annecs_fd_ = UniqueFd(*annecs);
  if (const int err = write_all(run.annecs_fd_.get(), annecs_header()))
    return Unexpected{(dir / kAnnecsFile).string() + ": " + errno_text(err)};
  sync_directory(dir);
  return run;
}

Expected<std::pair<RunDirectory, RunState>> RunDirectory::resume(const fs::path& dir, OpenFor purpose) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return Unexpected{dir.string() + ": no such directory (nothing to resume)"};
  Expected<RunLock> lock = RunLock::acquire(dir);
  if (!lock) return Unexpected{lock.error()};
  const fs::path checkpoint_path = dir / kCheckpointFile;

  // the checkpoint: the file's integrity, the directory's own fields, then the state's checks
  Expected<pb::Checkpoint> checkpoint = read_checkpoint_file(checkpoint_path);
  if (!checkpoint && checkpoint.error() == checkpoint_path.string() + ": " + kDoesNotExist)
    return Unexpected{checkpoint.error() + " (" + dir.string() + " holds no run to resume)"};
  if (!checkpoint) return Unexpected{checkpoint.error()};
  for (const auto& [name, present, value] :
       {std::tuple{"events_bytes", checkpoint->has_events_bytes(), checkpoint->events_bytes()},
        std::tuple{"stats_bytes", checkpoint->has_stats_bytes(), checkpoint->stats_bytes()}}) {
    if (!present) return Unexpected{checkpoint_path.string() + ": " + name + ": missing"};
    if (value < 0)
      return Unexpected{checkpoint_path.string() + ": " + name + ": must be >= 0 (got " + std::to_string(value) + ")"};
  }
  // A later build's checkpoint is named as such before the state's checks, whose rules that build may have changed.
  const std::optional<std::string> unknown_fields = unknown_fields_refusal(*checkpoint);
  if (unknown_fields && purpose == OpenFor::kComputing)
    return Unexpected{checkpoint_path.string() + ": " + *unknown_fields};
  Expected<RunState> state = from_checkpoint(*checkpoint);
  if (!state)
    return Unexpected{checkpoint_path.string() + ": " + state.error() +
                      (unknown_fields ? " (" + *unknown_fields + ")" : std::string())};
  if (purpose == OpenFor::kComputing) {
    if (const std::optional<std::string> refusal = arithmetic_refusal(
            checkpoint->has_arithmetic_digest() ? std::optional(checkpoint->arithmetic_digest()) : std::nullopt))
      return Unexpected{checkpoint_path.string() + ": " + *refusal};
  }

  // the logs, cut back to what the state has seen
  RunDirectory run(dir, std::move(*lock));
  run.config_ = checkpoint->config();
  Expected<int> events = open_log(dir / kEventsFile, checkpoint->events_bytes() == 0 ? O_CREAT : 0);
  if (!events) return Unexpected{events.error()};
  run.events_fd_ = UniqueFd(*events);
  Expected<int> stats = open_log(dir / kStatsFile, 0);
  if (!stats) return Unexpected{stats.error()};
  run.stats_fd_ = UniqueFd(*stats);
  if (auto error = truncate_log(run.events_fd_.get(), dir / kEventsFile, checkpoint->events_bytes()))
    return Unexpected{*error};
  if (auto error = truncate_log(run.stats_fd_.get(), dir / kStatsFile, checkpoint->stats_bytes()))
    return Unexpected{*error};
  Expected<uint32_t> events_crc = checked_log_crc(dir / kEventsFile, checkpoint->events_bytes(),
                                                  checkpoint->has_events_crc32(), checkpoint->events_crc32());
  if (!events_crc) return Unexpected{events_crc.error()};
  Expected<uint32_t> stats_crc = checked_log_crc(dir / kStatsFile, checkpoint->stats_bytes(),
                                                 checkpoint->has_stats_crc32(), checkpoint->stats_crc32());
  if (!stats_crc) return Unexpected{stats_crc.error()};
  run.events_crc_ = *events_crc;
  run.stats_crc_ = *stats_crc;
  for (const char* sub : {kEnvsDir, kPoliciesDir}) {
    fs::create_directories(dir / sub, ec);
    if (ec) return Unexpected{(dir / sub).string() + ": cannot create directory: " + ec.message()};
    remove_temporaries(dir / sub);
    if (auto error = probe_writable(dir / sub)) return Unexpected{*error};
  }
  remove_temporaries(dir);
  if (auto error = probe_writable(dir)) return Unexpected{*error};

  // config.textproto is the checkpoint's config for people and tools; one missing or changed is written again
  const std::string config_text = run_config_text(run.config_);
  if (!same_content(dir / kConfigFile, config_text)) {
    const bool present = fs::exists(dir / kConfigFile, ec);
    if (auto error = run.write_config(run.config_)) return Unexpected{*error};
    run.repairs_.push_back((dir / kConfigFile).string() +
                           (present ? " differed from the run's config (a run's config is its checkpoint's; to change "
                                      "it, start a new run)"
                                    : " was missing") +
                           ": written again from the checkpoint");
  }

  // annecs.csv, the state's lines (a crash after the checkpoint may have left later ones)
  if (const std::string annecs_lines = annecs_text(*state); !same_content(dir / kAnnecsFile, annecs_lines))
    if (auto error = write_named(dir / kAnnecsFile, annecs_lines)) return Unexpected{*error};
  Expected<int> annecs = open_log(dir / kAnnecsFile, 0);
  if (!annecs) return Unexpected{annecs.error()};
  run.annecs_fd_ = UniqueFd(*annecs);

  // the pair files, up to the checkpoint's state (a crash after the checkpoint's write may have left them behind)
  if (auto error = run.write_pair_files(*state, 0, /*only_changed=*/true)) return Unexpected{*error};
  run.pairs_with_env_files_ = state->pairs.size();
  for (const Pair& pair : state->pairs)
    if (pair.active()) run.active_at_last_save_.insert(pair.id);
  return std::pair<RunDirectory, RunState>(std::move(run), std::move(*state));
}

void RunDirectory::append(const IterationReport& report) {
  if (append_error_) return;  // the logs are already inconsistent with any further checkpoint
  std::string events;
  for (const auto& event : events_json(report))
    events += event.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  std::string stats;
  for (const PairStatsRow& row : report.stats) stats += pair_stats_row(row);
  if (const int err = write_all(events_fd_.get(), events)) {
    append_error_ = (dir_ / kEventsFile).string() + ": " + errno_text(err);
  } else if (const int err2 = write_all(stats_fd_.get(), stats)) {
    append_error_ = (dir_ / kStatsFile).string() + ": " + errno_text(err2);
  } else if (const int err3 = write_all(annecs_fd_.get(), annecs_line(report.iteration, report.annecs))) {
    append_error_ = (dir_ / kAnnecsFile).string() + ": " + errno_text(err3);
  } else {
    events_crc_ = crc32_extend(events_crc_, events);
    stats_crc_ = crc32_extend(stats_crc_, stats);
  }
}

std::optional<std::string> RunDirectory::write_pair_files(const RunState& state, size_t first_new, bool only_changed) {
  fs::path current;  // the file being written, for an exception's message
  auto write = [&](const fs::path& path, const std::string& text) -> std::optional<std::string> {
    current = path;
    if (only_changed && same_content(path, text)) return std::nullopt;
    return write_named(path, text);
  };
  try {
    for (size_t i = first_new; i < state.pairs.size(); ++i) {
      const Pair& pair = state.pairs[i];
      if (auto error = write(dir_ / kEnvsDir / pair_file(pair.id, ".env.json"), env_def_json_text(pair.env)))
        return error;
    }
    for (const Pair& pair : state.pairs) {
      if (!only_changed && !pair.active() && !active_at_last_save_.contains(pair.id)) continue;
      if (auto error =
              write(dir_ / kPoliciesDir / pair_file(pair.id, ".json"), policy_json_text(pair.theta, pair.latest_score)))
        return error;
      if (pair.best_theta.empty()) continue;  // no evaluation yet
      if (auto error = write(dir_ / kPoliciesDir / pair_file(pair.id, ".best.json"),
                             policy_json_text(pair.best_theta, pair.best_score)))
        return error;
    }
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {  // a non-finite θ or score: refused by the file formats
    return current.string() + ": " + e.what();
  }
  return std::nullopt;
}

std::optional<std::string> RunDirectory::save(const RunState& state) {
  if (append_error_) return append_error_;

  // the logs first: the checkpoint must never count bytes that a crash could still lose
  const std::pair<int, const char*> logs[] = {{events_fd_.get(), kEventsFile}, {stats_fd_.get(), kStatsFile}};
  int64_t sizes[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    const fs::path path = dir_ / logs[i].second;
    if (const int err = fsync_retrying(logs[i].first)) return path.string() + ": fsync: " + errno_text(err);
    Expected<int64_t> size = file_size(logs[i].first, path);
    if (!size) return size.error();
    sizes[i] = *size;
  }
  // annecs.csv is not counted by the checkpoint (resume recomputes it), only made durable with it
  if (const int err = fsync_retrying(annecs_fd_.get()))
    return (dir_ / kAnnecsFile).string() + ": fsync: " + errno_text(err);

  const uint32_t crcs[2] = {events_crc_, stats_crc_};
  const std::string bytes = encode_checkpoint_file(checkpoint_with_logs(config_, state, sizes, crcs));
  if (auto error = write_named(dir_ / kCheckpointFile, bytes)) return error;

  // then the pair files: a failure here leaves them behind the checkpoint, never ahead of it
  const size_t first_new = pairs_with_env_files_;
  std::optional<std::string> error = write_pair_files(state, first_new, /*only_changed=*/false);
  pairs_with_env_files_ = state.pairs.size();
  active_at_last_save_.clear();
  for (const Pair& pair : state.pairs)
    if (pair.active()) active_at_last_save_.insert(pair.id);
  return error;
}

std::optional<std::string> RunDirectory::write_config(const pb::RunConfig& config) {
  config_ = config;
  return write_named(dir_ / kConfigFile, run_config_text(config));
}

}  // namespace poet
