#pragma once
// The files of one run, in one directory:
//   config.textproto        the run's config (run_config_text), rewritten when a resume changes the limit
//   run.lock                the owner's advisory lock (run_lock.h): one process per run directory
//   checkpoint.pb           the state (checkpoint_file.h), replaced atomically (temporary file, fsync, rename,
//                           fsync of the directory)
//   events.jsonl            one JSON object per line: every event of every iteration
//   pair_stats.csv          a header, then one row per ES step (PairStatsRow)
//   annecs.csv              a header, then both ANNECS counts at the end of each iteration (run/annecs_log.h)
//   envs/pair-<id>.env.json          each pair's environment, written once when the pair first appears
//   policies/pair-<id>.json          its current θ with its latest score   } rewritten at each checkpoint while
//   policies/pair-<id>.best.json     its best θ with its best score        } active, and once after it retires
//   wall_times.csv          the machine time at each saved iteration (run/wall_times.h; the coordinator writes it,
//                           outside the run's determinism)
//   refused_keys.txt        with CURVE workers: the public keys refused for wrong results, one per line, kept for
//                           the run across resumes (curve_authenticator.h; the coordinator's, not the run's state)
// The checkpoint records the sizes of the two logs and their CRC-32; resume truncates them back, so after a crash
// the logs hold exactly the iterations the restored state has seen and a resumed run writes the same bytes as an
// uninterrupted one, and refuses logs whose bytes differ from those the checkpoint has seen. The logs are the
// run's history and cannot be rebuilt (only recomputed, by running the config again); config.textproto, envs/ and
// policies/ are derived from the checkpoint and resume writes them again when they are missing or differ; so is
// annecs.csv, whose lines are a function of the state (written again, it holds the state's iterations only). The pair
// files are written after the checkpoint, so they never run ahead of it (a failure or crash between the two leaves them
// behind), and resume brings them up to the checkpoint's state. Errors come back as messages naming the file; nothing
// throws except std::bad_alloc. Not thread-safe: one owner (the coordinator's main loop), and one RunDirectory per
// directory across processes (the lock).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common/plumbing/expected.h"
#include "common/plumbing/unique_fd.h"
#include "engine/iteration_report.h"
#include "engine/run_state.h"
#include "poet.pb.h"
#include "run_directory/files/checkpoint.h"
#include "run_directory/files/checkpoint_file.h"
#include "run_directory/files/run_lock.h"

namespace poet {

inline constexpr char kConfigFile[] = "config.textproto";
inline constexpr char kCheckpointFile[] = "checkpoint.pb";
inline constexpr char kEventsFile[] = "events.jsonl";
inline constexpr char kStatsFile[] = "pair_stats.csv";
inline constexpr char kEnvsDir[] = "envs";
inline constexpr char kPoliciesDir[] = "policies";
inline constexpr char kRefusedKeysFile[] = "refused_keys.txt";
inline constexpr std::uintmax_t kMaxRefusedKeysBytes = 1 << 20;  // 41 bytes a key: some 25,000 keys

// The header line of pair_stats.csv, and one row (both with their newline). Doubles are written in the shortest
// form that reads back to the same bits; an environment name with a comma, quote or newline is quoted.
std::string pair_stats_header();
std::string pair_stats_row(const PairStatsRow& row);

// The error for a log whose first `size` bytes, those a checkpoint has seen, no longer have its CRC-32.
std::string log_changed_error(const std::filesystem::path& path, int64_t size);

class RunDirectory {
 public:
  // Makes dir (and its parents), takes its lock and starts a run in it: config.textproto, empty logs (the stats
  // header only), envs/ and policies/. Refuses a directory that another process owns, that already holds
  // checkpoint.pb, that holds an earlier run's logs or pair files without it (naming them), or where no file
  // can be written. The caller saves the initial state next; until then the directory holds no run (a later
  // create may start over in it).
  static Expected<RunDirectory> create(const std::filesystem::path& dir, const pb::RunConfig& config);

  // Takes the lock, reads and checks checkpoint.pb (read_checkpoint_file, from_checkpoint), restores the state,
  // truncates the logs to the sizes the checkpoint records and checks their CRC-32, removes temporary files an
  // interrupted write left, checks that files can be written, and rewrites config.textproto, annecs.csv and the
  // pair files where they differ from the state's (repairs() says which of the first). A directory another process
  // owns, or a missing, corrupt or inconsistent run is an error; so is, for computing, a checkpoint holding fields
  // this build does not know (unknown_fields_refusal) or written by a process whose arithmetic differs
  // (arithmetic_refusal).
  static Expected<std::pair<RunDirectory, RunState>> resume(const std::filesystem::path& dir,
                                                            OpenFor purpose = OpenFor::kComputing);

  RunDirectory(RunDirectory&& other) noexcept = default;
  RunDirectory& operator=(RunDirectory&& other) noexcept = default;
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;
  ~RunDirectory() = default;

  // Appends the report's events, stats rows and ANNECS line to their files (written through, no user-space buffer). A
  // write error is kept and returned by the next save(), which then writes no checkpoint: the last one stays valid.
  void append(const IterationReport& report);

  // Makes the logs durable (fsync), writes the checkpoint of state with the logs' sizes, then the environment
  // files of new pairs and the policy files. Returns an error message naming the file, or nothing.
  std::optional<std::string> save(const RunState& state);

  // The run's config, which each checkpoint records; write_config replaces it and rewrites config.textproto
  // (after a resume changed the iteration limit).
  const pb::RunConfig& config() const { return config_; }
  std::optional<std::string> write_config(const pb::RunConfig& config);

  const std::filesystem::path& path() const { return dir_; }
  // What resume() put right (a config.textproto missing or changed), for the log.
  const std::vector<std::string>& repairs() const { return repairs_; }

 private:
  RunDirectory(std::filesystem::path dir, RunLock lock);
  // Writes the env files of pairs [first_new, n) and the policy files of active pairs and of those active at the
  // last save; with only_changed, every pair's files, each written only when its content differs.
  std::optional<std::string> write_pair_files(const RunState& state, size_t first_new, bool only_changed);

  std::filesystem::path dir_;
  RunLock lock_;
  pb::RunConfig config_;
  UniqueFd events_fd_;  // opened O_APPEND
  UniqueFd stats_fd_;
  UniqueFd annecs_fd_;       // derived from the state: no size or CRC in the checkpoint
  uint32_t events_crc_ = 0;  // CRC-32 of each log's bytes so far
  uint32_t stats_crc_ = 0;
  std::vector<std::string> repairs_;
  std::optional<std::string> append_error_;  // the first failed append, sticky
  size_t pairs_with_env_files_ = 0;          // state.pairs[0, n) have their env file
  std::set<int> active_at_last_save_;        // their policy files are rewritten once more after retiring
};

}  // namespace poet
