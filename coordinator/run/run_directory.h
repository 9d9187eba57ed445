#pragma once
// The files of one run, in one directory:
//   config.textproto        the run's config (run_config_text), rewritten when a resume changes the limit
//   checkpoint.pb           pb::Checkpoint, replaced atomically (temporary file, fsync, rename, fsync of the dir)
//   events.jsonl            one JSON object per line: every event of every iteration
//   pair_stats.csv          a header, then one row per ES step (PairStatsRow)
//   envs/pair-<id>.env.json          each pair's environment, written once when the pair first appears
//   policies/pair-<id>.json          its current θ with its latest score   } rewritten at each checkpoint while
//   policies/pair-<id>.best.json     its best θ with its best score        } active, and once after it retires
// The checkpoint records the sizes of the two logs; resume truncates them back, so after a crash the logs hold
// exactly the iterations the restored state has seen and a resumed run writes the same bytes as an
// uninterrupted one. Errors come back as messages naming the file; nothing throws except std::bad_alloc.
// Not thread-safe: one owner (the coordinator's main loop).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "expected.h"
#include "poet.pb.h"
#include "poet/iteration_report.h"
#include "poet/run_state.h"

namespace poet {

inline constexpr char kConfigFile[] = "config.textproto";
inline constexpr char kCheckpointFile[] = "checkpoint.pb";
inline constexpr char kEventsFile[] = "events.jsonl";
inline constexpr char kStatsFile[] = "pair_stats.csv";
inline constexpr char kEnvsDir[] = "envs";
inline constexpr char kPoliciesDir[] = "policies";

// A checkpoint larger than this is refused unread: a pair takes about 90 KB, so this is some ten thousand pairs.
inline constexpr std::uintmax_t kMaxCheckpointBytes = std::uintmax_t{1} << 30;

// The header line of pair_stats.csv, and one row (both with their newline). Doubles are written in the shortest
// form that reads back to the same bits; an environment name with a comma, quote or newline is quoted.
std::string pair_stats_header();
std::string pair_stats_row(const PairStatsRow& row);

class RunDirectory {
 public:
  // Makes dir (and its parents) and starts a run in it: config.textproto, empty logs (the stats header only),
  // envs/ and policies/. Refuses a directory that already holds checkpoint.pb. The caller saves the initial
  // state next; until then the directory holds no run (a later create may start over in it).
  static Expected<RunDirectory> create(const std::filesystem::path& dir, const pb::RunConfig& config);

  // Reads and checks checkpoint.pb (at most kMaxCheckpointBytes), restores the state and truncates the logs to
  // the sizes the checkpoint records. A missing, corrupt or inconsistent run is an error, and nothing is changed.
  static Expected<std::pair<RunDirectory, RunState>> resume(const std::filesystem::path& dir);

  RunDirectory(RunDirectory&& other) noexcept;
  RunDirectory& operator=(RunDirectory&& other) noexcept;
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;
  ~RunDirectory();

  // Appends the report's events and stats rows to the logs (written through, no user-space buffer). A write
  // error is kept and returned by the next save(), which then writes no checkpoint: the last one stays valid.
  void append(const IterationReport& report);

  // Makes the logs durable (fsync), writes the environment files of new pairs and the policy files, then the
  // checkpoint of state with the logs' sizes. Returns an error message naming the file, or nothing.
  std::optional<std::string> save(const RunState& state);

  // Rewrites config.textproto (after a resume changed the iteration limit).
  std::optional<std::string> write_config(const pb::RunConfig& config);

  const std::filesystem::path& path() const { return dir_; }

 private:
  RunDirectory(std::filesystem::path dir, int events_fd, int stats_fd);
  void close_logs();
  std::optional<std::string> write_pair_files(const RunState& state);

  std::filesystem::path dir_;
  int events_fd_ = -1;  // opened O_APPEND
  int stats_fd_ = -1;
  std::optional<std::string> append_error_;  // the first failed append, sticky
  size_t pairs_with_env_files_ = 0;          // state.pairs[0, n) have their env file
  std::set<int> active_at_last_save_;        // their policy files are rewritten once more after retiring
};

}  // namespace poet
