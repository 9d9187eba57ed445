#include "run_directory/reading/pair_stats_log.h"

#include <fstream>
#include <memory>
#include <optional>
#include <utility>

#include "common/text/csv_fields.h"
#include "run_directory/reading/log_lines.h"

namespace poet {

Expected<StatsColumns> StatsColumns::from_header(std::string_view line) {
  StatsColumns columns;
  const std::vector<std::string> header = csv_fields(line);
  columns.count_ = header.size();
  for (size_t i = 0; i < header.size(); ++i) columns.index_.emplace(header[i], i);
  for (const char* required : {"iteration", "pair", "score", "finished", "best_score", "solved", "es_steps"})
    if (!columns.index_.count(required))
      return Unexpected{std::string("the header has no column \"") + required + "\""};
  return columns;
}

Expected<StatsRow> StatsColumns::row(std::string_view line) const {
  const std::vector<std::string> f = csv_fields(line);
  if (f.size() != count_)
    return Unexpected{std::to_string(f.size()) + " fields, the header has " + std::to_string(count_)};
  const auto field = [&](const char* name) -> const std::string* {
    const auto found = index_.find(name);
    return found == index_.end() ? nullptr : &f[found->second];
  };
  const auto bad = [](const char* name) { return Unexpected{std::string(name) + ": not a valid value"}; };
  StatsRow row;
  if (!parse_field(*field("iteration"), row.iteration)) return bad("iteration");
  if (!parse_field(*field("pair"), row.pair)) return bad("pair");
  if (!parse_field(*field("score"), row.score)) return bad("score");
  if (!parse_field(*field("best_score"), row.best_score)) return bad("best_score");
  if (!parse_field(*field("es_steps"), row.es_steps)) return bad("es_steps");
  row.finished = *field("finished") == "true";
  row.solved = *field("solved") == "true";
  // columns added later: absent in older runs
  if (const std::string* rollouts = field("run_rollouts"); rollouts && !parse_field(*rollouts, row.run_rollouts))
    return bad("run_rollouts");
  if (const std::string* steps = field("run_env_steps"); steps && !parse_field(*steps, row.run_env_steps))
    return bad("run_env_steps");
  if (const std::string* steps = field("pair_env_steps"); steps && !parse_field(*steps, row.pair_env_steps))
    return bad("pair_env_steps");
  return row;
}

PairEnvStepsAt pair_env_steps_at(const std::vector<StatsRow>& rows) {
  auto recorded = std::make_shared<std::map<std::pair<int, int>, int64_t>>();
  for (const StatsRow& row : rows)
    if (row.pair_env_steps >= 0) (*recorded)[{row.pair, row.iteration}] = row.pair_env_steps;
  return [recorded](int pair, int iteration) -> std::optional<int64_t> {
    const auto found = recorded->find({pair, iteration});
    if (found == recorded->end()) return std::nullopt;
    return found->second;
  };
}

Expected<std::vector<StatsRow>> parse_stats(const std::filesystem::path& path, std::string_view bytes) {
  const LogLines log = whole_lines(bytes);
  if (log.consumed != bytes.size())
    return Unexpected{path.string() + ": the last line recorded by the checkpoint is cut"};
  if (log.lines.empty()) return Unexpected{path.string() + ": no header line"};
  const Expected<StatsColumns> columns = StatsColumns::from_header(log.lines[0]);
  if (!columns) return Unexpected{path.string() + ": " + columns.error()};
  std::vector<StatsRow> rows;
  for (size_t n = 1; n < log.lines.size(); ++n) {
    Expected<StatsRow> row = columns->row(log.lines[n]);
    if (!row) return Unexpected{path.string() + ":" + std::to_string(n + 1) + ": " + row.error()};
    rows.push_back(*row);
  }
  return rows;
}

std::vector<StatsRow> PairStatsTail::rows_of(int pair) {
  read_on();
  const auto found = rows_.find(pair);
  return found == rows_.end() ? std::vector<StatsRow>{} : found->second;
}

void PairStatsTail::read_on() {
  std::ifstream in(path_, std::ios::binary);
  if (!in) return;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return;
  if (static_cast<uint64_t>(size) < offset_) *this = PairStatsTail(path_);  // the file was cut back: start over
  in.seekg(static_cast<std::streamoff>(offset_));

  // read on in blocks; only whole lines are consumed, a partial last one is read again next time
  std::string pending;
  std::vector<char> block(1 << 20);
  while (in.read(block.data(), static_cast<std::streamsize>(block.size())) || in.gcount() > 0) {
    pending.append(block.data(), static_cast<size_t>(in.gcount()));
    const LogLines log = whole_lines(pending);
    for (std::string_view line : log.lines) read_line(line);
    offset_ += log.consumed;
    pending.erase(0, log.consumed);
  }
}

void PairStatsTail::read_line(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  if (!header_read_) {
    header_read_ = true;
    columns_ = StatsColumns::from_header(line);
    return;
  }
  if (!columns_) return;  // a header without the columns: no scores to show
  if (Expected<StatsRow> row = columns_->row(line)) rows_[row->pair].push_back(*row);
}

}  // namespace poet
