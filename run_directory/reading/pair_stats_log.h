#pragma once
// The one reader of pair_stats.csv (a header, then a row per ES step), in the two ways it is read: the rows a
// checkpoint vouches for, strictly (the analysis tools' RunSnapshot), and a live log read on as it grows, rows
// that do not parse skipped (the status socket's /pairs/{id}).

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "common/plumbing/expected.h"
#include "engine/lineage.h"

namespace poet {

// One row of pair_stats.csv, the columns the analysis reads. run_rollouts, run_env_steps and pair_env_steps
// are -1 in runs written before those columns existed.
struct StatsRow {
  int iteration = 0;
  int pair = 0;
  double score = 0;
  bool finished = false;
  double best_score = 0;
  bool solved = false;
  int64_t es_steps = 0;
  int64_t run_rollouts = -1;
  int64_t run_env_steps = -1;
  int64_t pair_env_steps = -1;  // the pair's environment steps in its own ES steps so far
};

// Where the columns are, from the header line. Columns are found by name, so rows of runs written before a
// column was added still read.
class StatsColumns {
 public:
  // An error names the first required column the header lacks.
  static Expected<StatsColumns> from_header(std::string_view line);
  // One row, or what is wrong with it ("3 fields, the header has 12", "score: not a valid value").
  Expected<StatsRow> row(std::string_view line) const;

 private:
  size_t count_ = 0;
  std::map<std::string, size_t, std::less<>> index_;
};

// bytes: the file up to a checkpoint's size. Every row must read; errors name path and the line's number.
Expected<std::vector<StatsRow>> parse_stats(const std::filesystem::path& path, std::string_view bytes);

// The pairs' environment steps after each ES step (pair_env_steps) as lineage_env_steps asks for them; nothing
// for a row without them (a run of a build before they were recorded).
PairEnvStepsAt pair_env_steps_at(const std::vector<StatsRow>& rows);

// A live pair_stats.csv read on from where the last call stopped (whole lines only; a file cut back is read
// again from its start). Not thread-safe: its owner locks.
class PairStatsTail {
 public:
  explicit PairStatsTail(std::filesystem::path path) : path_(std::move(path)) {}
  // The rows of a pair read so far, in file order, after reading on.
  std::vector<StatsRow> rows_of(int pair);

 private:
  void read_on();
  void read_line(std::string_view line);

  std::filesystem::path path_;
  uint64_t offset_ = 0;  // bytes consumed: whole lines only
  bool header_read_ = false;
  Expected<StatsColumns> columns_ = Unexpected{std::string("no header yet")};
  std::map<int, std::vector<StatsRow>> rows_;
};

}  // namespace poet
