#include "tools/status_client/status_tables.h"

#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>
#include <vector>

#include "common/text/event_text.h"
#include "common/text/text_format.h"
#include "common/text/utf8.h"

namespace poet {
namespace {

// ---------------------------------------------------------------------------------------------------------
// formatting

// Text to stdout as it is: only for text made printable already.
void write_out(const std::string& text) { std::fwrite(text.data(), 1, text.size(), stdout); }

// printf to stdout, the text made printable first: what it prints comes from the server, whose strings may hold
// escape sequences meant for the terminal.
[[gnu::format(printf, 1, 2)]] void say(const char* format, ...) {
  va_list args;
  va_start(args, format);
  const std::string text = vprintf_text(format, args);
  va_end(args);
  write_out(printable_text(text));
}

// A value as people read it in a table: whole numbers written out in full, others as number_text writes them.
std::string table_number(double value) {
  if (!std::isfinite(value)) return value > 0 ? "inf" : value < 0 ? "-inf" : "nan";
  if (value == std::floor(value) && std::abs(value) < 1e15) return std::to_string(static_cast<long long>(value));
  return poet::number_text(value);
}

std::string fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string duration(double seconds) {
  if (seconds < 60) return fixed(seconds, 1) + " s";
  const auto total = static_cast<long long>(seconds);
  char text[64];
  if (total < 3600) {
    std::snprintf(text, sizeof text, "%lld min %02lld s", total / 60, total % 60);
  } else {
    std::snprintf(text, sizeof text, "%lld h %02lld min", total / 3600, total % 3600 / 60);
  }
  return text;
}

std::string iteration_or_dash(int iteration) { return iteration < 0 ? "-" : std::to_string(iteration); }

// Characters as a terminal shows them: UTF-8 continuation bytes take no column.
size_t display_width(const std::string& text) {
  return static_cast<size_t>(
      std::count_if(text.begin(), text.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

// A table: columns sized to their widest cell, numbers right-aligned.
class Table {
 public:
  explicit Table(std::vector<std::string> header) { rows_.push_back(std::move(header)); }
  // the cells made printable here, so that the columns are sized as they will show (and print() writes them as
  // they are); the header is ours
  void add(std::vector<std::string> row) {
    for (std::string& cell : row) cell = printable_text(cell);
    rows_.push_back(std::move(row));
  }
  void print() const {
    // a column is numeric (right-aligned) when every cell below the header is a number or "-"
    const size_t columns = rows_[0].size();
    std::vector<size_t> width(columns, 0);
    std::vector<bool> numeric(columns, true);
    for (size_t r = 0; r < rows_.size(); ++r) {
      for (size_t i = 0; i < columns && i < rows_[r].size(); ++i) {
        const std::string& cell = rows_[r][i];
        width[i] = std::max(width[i], display_width(cell));
        const size_t digit = cell.starts_with('-') ? 1 : 0;
        if (r > 0 && cell != "-" && (cell.size() <= digit || !std::isdigit(static_cast<unsigned char>(cell[digit]))))
          numeric[i] = false;
      }
    }
    for (const auto& row : rows_) {
      std::string line;
      for (size_t i = 0; i < columns && i < row.size(); ++i) {
        const std::string pad(width[i] - display_width(row[i]), ' ');
        line += (i ? "  " : "") + (numeric[i] ? pad + row[i] : row[i] + (i + 1 < row.size() ? pad : ""));
      }
      write_out(line + "\n");
    }
  }

 private:
  std::vector<std::vector<std::string>> rows_;
};

std::string value_text(const google::protobuf::Value& value) {
  switch (value.kind_case()) {
    case google::protobuf::Value::kStringValue:
      return value.string_value();
    case google::protobuf::Value::kNumberValue:
      return table_number(value.number_value());
    case google::protobuf::Value::kBoolValue:
      return value.bool_value() ? "true" : "false";
    case google::protobuf::Value::kNullValue:
      return "null";
    default: {
      std::string text;
      (void)google::protobuf::util::MessageToJsonString(value, &text);
      return text;
    }
  }
}

}  // namespace

EventView event_view(const google::protobuf::Struct& event) {
  const auto& fields = event.fields();
  EventView view;
  if (const auto iteration = fields.find("iteration"); iteration != fields.end())
    view.iteration = value_text(iteration->second);
  if (const auto name = fields.find("event"); name != fields.end()) view.name = value_text(name->second);
  for (const auto& [key, value] : fields)
    if (key != "iteration" && key != "event")
      view.fields.emplace_back(key, value.kind_case() == google::protobuf::Value::kNumberValue
                                        ? reading_text(value.number_value())
                                        : value_text(value));
  std::sort(view.fields.begin(), view.fields.end());  // a protobuf map has no order of its own
  return view;
}

// ---------------------------------------------------------------------------------------------------------
// the commands' printers

void print_status(const status::Status& s) {
  say("run         %s (%s, seed %llu)\n", s.run_dir().c_str(), s.mode().empty() ? "-" : s.mode().c_str(),
      static_cast<unsigned long long>(s.seed()));
  say("state       %s%s%s\n", s.state().c_str(), s.note().empty() ? "" : ": ", s.note().c_str());
  say("iteration   %d of %d%s, checkpoint at %d\n", s.iteration(), s.iterations(), s.finished() ? " (finished)" : "",
      s.last_checkpoint_iteration());
  say("pairs       %d created, %d active, %d solved\n", s.pairs_created(), s.pairs_active(), s.pairs_solved());
  say("transfers   %lld accepted of %lld attempted\n", static_cast<long long>(s.transfer_successes()),
      static_cast<long long>(s.transfer_attempts()));
  say("ANNECS      %d at admission, %d at archiving\n", s.annecs_at_admission(), s.annecs_at_archiving());
  if (s.has_frontier_solved() && s.has_frontier_admitted()) {
    const status::ObstacleMeasures& solved = s.frontier_solved();
    const status::ObstacleMeasures& admitted = s.frontier_admitted();
    say("frontier    roughness %s, gap top %s, stump top %s solved (%s, %s, %s admitted); hardest level solved: %s\n",
        fixed(solved.roughness(), 1).c_str(), fixed(solved.gap_hi(), 1).c_str(), fixed(solved.stump_hi(), 1).c_str(),
        fixed(admitted.roughness(), 1).c_str(), fixed(admitted.gap_hi(), 1).c_str(),
        fixed(admitted.stump_hi(), 1).c_str(),
        s.highest_level_solved().empty() ? "none" : s.highest_level_solved().c_str());
  }
  say("workers     %d, %lld jobs queued, %lld in flight\n", s.workers(), static_cast<long long>(s.queue_depth()),
      static_cast<long long>(s.in_flight_jobs()));
  say("rollouts    %lld (%s/s)\n", static_cast<long long>(s.rollouts()), fixed(s.rollouts_per_s(), 1).c_str());
  say("env steps   %lld (%s/s)\n", static_cast<long long>(s.env_steps()), fixed(s.env_steps_per_s(), 0).c_str());
  say("uptime      %s\n", duration(s.uptime_s()).c_str());
  std::string dropped;
  for (const auto& [reason, count] : s.dropped_frames())
    if (count > 0) dropped += (dropped.empty() ? "" : ", ") + reason + " " + std::to_string(count);
  if (!dropped.empty()) say("dropped     %s\n", dropped.c_str());
}

void print_pairs(const status::PairList& list) {
  Table table({"id", "env", "state", "created", "parent", "latest", "best", "solved", "es_steps", "difficulty"});
  for (const status::PairSummary& p : list.pairs()) {
    table.add({std::to_string(p.id()), p.env(),
               p.active() ? "active" : "retired@" + std::to_string(p.retired_iteration()),
               std::to_string(p.created_iteration()), iteration_or_dash(p.parent_id()), fixed(p.latest_score(), 1),
               fixed(p.best_score(), 1), p.solved() ? "@" + std::to_string(p.first_solved_iteration()) : "no",
               std::to_string(p.es_steps()), p.difficulty()});
  }
  table.print();
  say("%d pairs\n", list.pairs_size());
}

void print_pair(const status::PairDetail& d) {
  const status::PairSummary& p = d.pair();
  const status::Lineage& l = d.lineage();
  say("pair %d on %s (seed %u), %s\n", p.id(), p.env().c_str(), p.seed(), p.difficulty().c_str());
  say("created     iteration %d%s; %s\n", p.created_iteration(),
      p.parent_id() < 0 ? " (the first pair)" : (" from pair " + std::to_string(p.parent_id())).c_str(),
      p.active() ? "active" : ("retired at iteration " + std::to_string(p.retired_iteration())).c_str());
  say("scores      latest %s, best %s (iteration %s); %s\n", fixed(p.latest_score(), 2).c_str(),
      fixed(p.best_score(), 2).c_str(), iteration_or_dash(p.best_iteration()).c_str(),
      p.solved() ? ("solved at iteration " + std::to_string(p.first_solved_iteration())).c_str() : "not solved");
  say("es steps    %lld\n", static_cast<long long>(p.es_steps()));
  std::string ancestors;
  for (int a : l.ancestors()) ancestors += (ancestors.empty() ? "" : " <- ") + std::to_string(a);
  say("ancestors   %s\n", ancestors.empty() ? "none" : ancestors.c_str());
  say("first θ     %s (admitted with %s)\n",
      l.initial_source_pair() < 0
          ? "fresh"
          : ("from pair " + std::to_string(l.initial_source_pair()) + (l.initial_by_proposal() ? ", a proposal" : ""))
                .c_str(),
      fixed(l.admission_score(), 2).c_str());
  say("transfers   %d accepted of %lld rounds\n", l.transfers_size(), static_cast<long long>(l.transfer_attempts()));
  for (const status::Transfer& t : l.transfers())
    say("            iteration %d from pair %d (%s), score %s\n", t.iteration(), t.source_pair(),
        t.proposal() ? "proposal" : "θ", fixed(t.score(), 2).c_str());
  constexpr int kShown = 20;
  const int n = d.scores_size();
  say("scores over iterations (%s%d rows; --json for all):\n", n > kShown ? "the last 20 of " : "", n);
  Table table({"iteration", "score", "best"});
  for (int i = std::max(0, n - kShown); i < n; ++i)
    table.add(
        {std::to_string(d.scores(i).iteration()), fixed(d.scores(i).score(), 2), fixed(d.scores(i).best_score(), 2)});
  table.print();
}

namespace {
std::string interval(const poet::pb::Interval& i) {
  return "[" + table_number(i.lo()) + ", " + table_number(i.hi()) + "]";
}
}  // namespace

void print_archive(const status::Archive& archive) {
  Table table({"id", "env", "seed", "state", "roughness", "pit gap", "stump height", "stair height"});
  for (const status::ArchiveEntry& e : archive.pairs()) {
    const auto& enc = e.encoding();
    table.add({std::to_string(e.id()), e.env(), std::to_string(e.seed()), e.active() ? "active" : "retired",
               table_number(enc.roughness()), enc.has_pit_gap() ? interval(enc.pit_gap()) : "-",
               enc.has_stump_height() ? interval(enc.stump_height()) : "-",
               enc.has_stair_height() ? interval(enc.stair_height()) : "-"});
  }
  table.print();
  say("%d environments\n", archive.pairs_size());
}

void print_workers(const status::WorkerList& list) {
  Table table({"id", "address", "threads", "trust", "checks", "jobs", "taken", "results", "heard", "fingerprint",
               "arithmetic"});
  for (const auto* workers : {&list.workers(), &list.refused()})
    for (const status::Worker& w : *workers)
      table.add({w.id(), w.address(), std::to_string(w.threads()), w.trust(), std::to_string(w.checks_passed()),
                 std::to_string(w.jobs_done()), std::to_string(w.answers_taken()), std::to_string(w.results_done()),
                 fixed(w.seconds_since_heartbeat(), 1) + " s ago", w.fingerprint_digest(), w.arithmetic_digest()});
  table.print();
  say("%d workers, %lld jobs queued, %lld in flight", list.workers_size(), static_cast<long long>(list.queue_depth()),
      static_cast<long long>(list.in_flight_jobs()));
  if (list.refused_size() > 0) say("; %d refused for wrong results", list.refused_size());
  say("\n");
}

void print_events(const status::EventList& list) {
  for (const google::protobuf::Struct& event : list.events()) say("%s\n", describe_event(event_view(event)).c_str());
  if (list.more())
    say("(more: poetctl events --since %lld)\n", static_cast<long long>(list.next()));
  else
    say("(%d events; next: --since %lld)\n", list.events_size(), static_cast<long long>(list.next()));
}

}  // namespace poet
