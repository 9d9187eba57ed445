// poetctl: asks a running poet-coordinator's status socket what its run is doing.
//   poetctl [--address HOST:PORT] [--json] status | pairs | pair ID | archive | workers | events [--since N]
//           [--limit M] | metrics
//   poetctl keygen DIR coordinator|worker [--authorize]
//   poetctl picture KIND OUT [--pair ID] [--run-dir DIR]   a picture of the live run, or of a run directory's files
// Prints a table for people, or with --json the server's JSON as it came (/metrics is always its text). The
// address is --address, else $POET_STATUS, else 127.0.0.1:8580. Exit codes: 0 done, 1 the coordinator cannot be
// reached or answered with an error (the message names the address), 2 bad command line or address.

#include <google/protobuf/util/json_util.h>
#include <httplib.h>
#include <zmq.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "canvas.h"
#include "curve_keys.h"
#include "report/run_pictures.h"
#include "report/run_snapshot.h"
#include "status.pb.h"
#include "status/status_server.h"
#include "tool_flags.h"
#include "text_format.h"

namespace poet {
namespace {

constexpr char kAddressVariable[] = "POET_STATUS";
constexpr int kExitUnreachable = 1;
constexpr time_t kConnectTimeoutS = 3;
constexpr time_t kReadTimeoutS = 5;

// ---------------------------------------------------------------------------------------------------------
// formatting

std::string number(double value) {
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
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
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
      std::printf("%s\n", line.c_str());
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
      return number(value.number_value());
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

// "iteration 12: pair_created pair=3 env=r0.4" from {"iteration": 12, "event": "pair_created", ...}.
std::string describe_event(const google::protobuf::Struct& event) {
  const auto& fields = event.fields();
  const auto iteration = fields.find("iteration");
  const auto name = fields.find("event");
  std::string text = iteration != fields.end() ? "iteration " + value_text(iteration->second) + ": " : "";
  text += name != fields.end() ? value_text(name->second) : "event";
  std::vector<std::string> keys;
  for (const auto& [key, value] : fields)
    if (key != "iteration" && key != "event") keys.push_back(key);
  std::sort(keys.begin(), keys.end());  // a protobuf map has no order of its own
  for (const std::string& key : keys) text += " " + key + "=" + value_text(fields.at(key));
  return text;
}

// ---------------------------------------------------------------------------------------------------------
// the commands' printers

void print_status(const status::Status& s) {
  std::printf("run         %s (%s, seed %llu)\n", s.run_dir().c_str(), s.mode().empty() ? "-" : s.mode().c_str(),
              static_cast<unsigned long long>(s.seed()));
  std::printf("state       %s%s%s\n", s.state().c_str(), s.note().empty() ? "" : ": ", s.note().c_str());
  std::printf("iteration   %d of %d%s, checkpoint at %d\n", s.iteration(), s.iterations(),
              s.finished() ? " (finished)" : "", s.last_checkpoint_iteration());
  std::printf("pairs       %d created, %d active, %d solved\n", s.pairs_created(), s.pairs_active(), s.pairs_solved());
  std::printf("transfers   %lld accepted of %lld attempted\n", static_cast<long long>(s.transfer_successes()),
              static_cast<long long>(s.transfer_attempts()));
  std::printf("workers     %d, %lld jobs queued, %lld in flight\n", s.workers(),
              static_cast<long long>(s.queue_depth()), static_cast<long long>(s.in_flight_jobs()));
  std::printf("rollouts    %lld (%s/s)\n", static_cast<long long>(s.rollouts()), fixed(s.rollouts_per_s(), 1).c_str());
  std::printf("env steps   %lld (%s/s)\n", static_cast<long long>(s.env_steps()),
              fixed(s.env_steps_per_s(), 0).c_str());
  std::printf("uptime      %s\n", duration(s.uptime_s()).c_str());
  std::string dropped;
  for (const auto& [reason, count] : s.dropped_frames())
    if (count > 0) dropped += (dropped.empty() ? "" : ", ") + reason + " " + std::to_string(count);
  if (!dropped.empty()) std::printf("dropped     %s\n", dropped.c_str());
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
  std::printf("%d pairs\n", list.pairs_size());
}

void print_pair(const status::PairDetail& d) {
  const status::PairSummary& p = d.pair();
  const status::Lineage& l = d.lineage();
  std::printf("pair %d on %s (seed %u), %s\n", p.id(), p.env().c_str(), p.seed(), p.difficulty().c_str());
  std::printf("created     iteration %d%s; %s\n", p.created_iteration(),
              p.parent_id() < 0 ? " (the first pair)" : (" from pair " + std::to_string(p.parent_id())).c_str(),
              p.active() ? "active" : ("retired at iteration " + std::to_string(p.retired_iteration())).c_str());
  std::printf(
      "scores      latest %s, best %s (iteration %s); %s\n", fixed(p.latest_score(), 2).c_str(),
      fixed(p.best_score(), 2).c_str(), iteration_or_dash(p.best_iteration()).c_str(),
      p.solved() ? ("solved at iteration " + std::to_string(p.first_solved_iteration())).c_str() : "not solved");
  std::printf("es steps    %lld\n", static_cast<long long>(p.es_steps()));
  std::string ancestors;
  for (int a : l.ancestors()) ancestors += (ancestors.empty() ? "" : " <- ") + std::to_string(a);
  std::printf("ancestors   %s\n", ancestors.empty() ? "none" : ancestors.c_str());
  std::printf("first θ     %s (admitted with %s)\n",
              l.initial_source_pair() < 0 ? "fresh"
                                          : ("from pair " + std::to_string(l.initial_source_pair()) +
                                             (l.initial_by_proposal() ? ", a proposal" : ""))
                                                .c_str(),
              fixed(l.admission_score(), 2).c_str());
  std::printf("transfers   %d accepted of %lld rounds\n", l.transfers_size(),
              static_cast<long long>(l.transfer_attempts()));
  for (const status::Transfer& t : l.transfers())
    std::printf("            iteration %d from pair %d (%s), score %s\n", t.iteration(), t.source_pair(),
                t.proposal() ? "proposal" : "θ", fixed(t.score(), 2).c_str());
  constexpr int kShown = 20;
  const int n = d.scores_size();
  std::printf("scores over iterations (%s%d rows; --json for all):\n", n > kShown ? "the last 20 of " : "", n);
  Table table({"iteration", "score", "best"});
  for (int i = std::max(0, n - kShown); i < n; ++i)
    table.add(
        {std::to_string(d.scores(i).iteration()), fixed(d.scores(i).score(), 2), fixed(d.scores(i).best_score(), 2)});
  table.print();
}

std::string interval(const poet::pb::Interval& i) { return "[" + number(i.lo()) + ", " + number(i.hi()) + "]"; }

void print_archive(const status::Archive& archive) {
  Table table({"id", "env", "seed", "state", "roughness", "pit gap", "stump height", "stair height"});
  for (const status::ArchiveEntry& e : archive.pairs()) {
    const auto& enc = e.encoding();
    table.add({std::to_string(e.id()), e.env(), std::to_string(e.seed()), e.active() ? "active" : "retired",
               number(enc.roughness()), enc.has_pit_gap() ? interval(enc.pit_gap()) : "-",
               enc.has_stump_height() ? interval(enc.stump_height()) : "-",
               enc.has_stair_height() ? interval(enc.stair_height()) : "-"});
  }
  table.print();
  std::printf("%d environments\n", archive.pairs_size());
}

void print_workers(const status::WorkerList& list) {
  Table table({"id", "address", "threads", "jobs", "results", "heard", "fingerprint"});
  for (const status::Worker& w : list.workers())
    table.add({w.id(), w.address(), std::to_string(w.threads()), std::to_string(w.jobs_done()),
               std::to_string(w.results_done()), fixed(w.seconds_since_heartbeat(), 1) + " s ago",
               w.fingerprint_digest()});
  table.print();
  std::printf("%d workers, %lld jobs queued, %lld in flight\n", list.workers_size(),
              static_cast<long long>(list.queue_depth()), static_cast<long long>(list.in_flight_jobs()));
}

void print_events(const status::EventList& list) {
  for (const google::protobuf::Struct& event : list.events()) std::printf("%s\n", describe_event(event).c_str());
  if (list.more())
    std::printf("(more: poetctl events --since %lld)\n", static_cast<long long>(list.next()));
  else
    std::printf("(%d events; next: --since %lld)\n", list.events_size(), static_cast<long long>(list.next()));
}

// ---------------------------------------------------------------------------------------------------------
// the request

template <class Message>
std::optional<Message> parse(const std::string& body, const std::string& what) {
  Message message;
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = true;  // a newer coordinator may say more
  if (!google::protobuf::util::JsonStringToMessage(body, &message, options).ok()) {
    std::fprintf(stderr, "poetctl: %s: the answer is not the JSON expected\n", what.c_str());
    return std::nullopt;
  }
  return message;
}

// What went wrong with a request, for people.
std::string failure(httplib::Error error) {
  switch (error) {
    case httplib::Error::Connection:
      return "cannot connect (nothing listens there, or no answer within " + std::to_string(kConnectTimeoutS) + " s)";
    case httplib::Error::Read:
      return "no complete answer within " + std::to_string(kReadTimeoutS) + " s";
    case httplib::Error::Write:
      return "the request could not be sent";
    default:
      return "request failed (" + httplib::to_string(error) + ")";
  }
}

struct Command {
  std::string path;                                    // with its query
  std::function<bool(const std::string& body)> print;  // false: the body could not be read
  std::function<int(const std::string& body)> save;    // instead of printing: keeps the body (an exit code)
};

int run(const std::string& address, const Command& command, bool json) {
  const Expected<HostPort> where = parse_host_port(address);
  if (!where) {
    std::fprintf(stderr, "poetctl: %s\n", where.error().c_str());
    return kExitUsage;
  }
  httplib::Client client(where->host, where->port);
  client.set_connection_timeout(kConnectTimeoutS, 0);
  client.set_read_timeout(kReadTimeoutS, 0);
  client.set_write_timeout(kReadTimeoutS, 0);
  const httplib::Result result = client.Get(command.path);
  const std::string what = "GET http://" + address + command.path;
  if (!result) {
    std::fprintf(stderr, "poetctl: cannot reach the coordinator at %s: %s\n", address.c_str(),
                 failure(result.error()).c_str());
    return kExitUnreachable;
  }
  if (result->status != 200) {
    std::string message = result->body;
    if (auto error = parse<status::Error>(result->body, what); error && !error->error().empty())
      message = error->error();
    std::fprintf(stderr, "poetctl: %s: %d %s\n", what.c_str(), result->status, message.c_str());
    return kExitUnreachable;
  }
  if (command.save) return command.save(result->body);
  if (json || !command.print) {
    std::fwrite(result->body.data(), 1, result->body.size(), stdout);
    return 0;
  }
  return command.print(result->body) ? 0 : kExitUnreachable;
}

template <class Message>
std::function<bool(const std::string&)> printer(void (*print)(const Message&), const std::string& what) {
  return [print, what](const std::string& body) {
    const std::optional<Message> message = parse<Message>(body, what);
    if (message) print(*message);
    return message.has_value();
  };
}

// poetctl picture: the request an output path asks for, or the message saying why not.
Expected<PictureRequest> picture_request(const std::string& kind_name, const std::string& out, int pair) {
  const std::optional<PictureKind> kind = picture_kind(kind_name);
  if (!kind) return Unexpected{"no picture \"" + kind_name + "\"; one of " + picture_kind_names()};
  const size_t dot = out.rfind('.');
  const std::optional<PictureEncoding> encoding =
      dot == std::string::npos ? std::nullopt : picture_encoding(out.substr(dot + 1));
  if (!encoding) return Unexpected{out + ": the file name must end in .png, .svg or .gif"};
  if (needs_pair(*kind) && pair < 0) return Unexpected{kind_name + " is a pair's picture: give --pair ID"};
  if (!needs_pair(*kind) && pair >= 0) return Unexpected{kind_name + " is the run's picture: no --pair"};
  const PictureRequest request{*kind, *encoding, pair};
  if (std::optional<std::string> problem = encoding_problem(request)) return Unexpected{*problem};
  return request;
}

// The picture from a run directory's files (read only), written to out.
int picture_from_files(const std::string& run_dir, const PictureRequest& request, const std::string& out) {
  if (is_inside(out, run_dir)) {
    std::fprintf(stderr, "poetctl picture: %s is inside the run directory; pictures are written elsewhere\n",
                 out.c_str());
    return kExitUsage;
  }
  Expected<RunSnapshot> run = read_run_snapshot(run_dir);
  if (!run) {
    std::fprintf(stderr, "poetctl picture: %s\n", run.error().c_str());
    return kExitUsage;
  }
  if (request.pair >= 0 && !run->state.find(request.pair)) {
    std::fprintf(stderr, "poetctl picture: no pair %d in %s (pairs 0 to %zu)\n", request.pair, run_dir.c_str(),
                 run->state.pairs.size() - 1);
    return kExitUsage;
  }
  Expected<std::string> bytes = render_run_picture(*run, request);
  if (!bytes) {
    std::fprintf(stderr, "poetctl picture: %s\n", bytes.error().c_str());
    return kExitUnreachable;
  }
  if (std::string error = write_bytes(out, *bytes); !error.empty()) {
    std::fprintf(stderr, "poetctl picture: %s\n", error.c_str());
    return kExitUnreachable;
  }
  std::printf("%s: %s, %zu bytes\n", out.c_str(), mime_type(request.encoding), bytes->size());
  return 0;
}

// The path of the status socket's picture endpoint for a request.
std::string picture_path(const std::string& kind_name, const std::string& out, const PictureRequest& request) {
  const std::string extension = out.substr(out.rfind('.') + 1);
  if (request.pair >= 0) return "/pictures/pairs/" + std::to_string(request.pair) + "/" + kind_name + "." + extension;
  return "/pictures/" + kind_name + "." + extension;
}

// poetctl keygen: a fresh pair from libzmq's generator, written without replacing any key.
int make_keys(const std::filesystem::path& dir, const std::string& name, bool authorize) {
  std::array<char, 41> public_key{};
  std::array<char, 41> secret_key{};
  if (zmq_curve_keypair(public_key.data(), secret_key.data()) != 0) {
    std::fprintf(stderr, "poetctl keygen: this libzmq cannot make CURVE keys: %s\n", zmq_strerror(zmq_errno()));
    return kExitUnreachable;
  }
  const CurveKeyPair keys{public_key.data(), secret_key.data()};
  if (auto error = write_key_pair(dir, name, keys)) {
    std::fprintf(stderr, "poetctl keygen: %s\n", error->c_str());
    return kExitUnreachable;
  }
  std::printf("%s/%s.key: %s\n", dir.c_str(), name.c_str(), keys.public_key.c_str());
  if (authorize && name != "worker") {
    std::fprintf(stderr, "poetctl keygen: --authorize is for worker keys\n");
    return kExitUsage;
  }
  if (authorize) {
    const std::filesystem::path authorized = dir / "authorized";
    std::error_code ec;
    std::filesystem::create_directories(authorized, ec);
    std::filesystem::copy_file(dir / (name + ".key"), authorized / (name + ".key"), ec);
    if (ec) {
      std::fprintf(stderr, "poetctl keygen: %s: %s\n", (authorized / (name + ".key")).c_str(), ec.message().c_str());
      return kExitUnreachable;
    }
    std::printf("authorised: %s\n", (authorized / (name + ".key")).c_str());
  }
  return 0;
}

}  // namespace
}  // namespace poet

int main(int argc, char** argv) {
  std::signal(SIGPIPE, SIG_IGN);  // a server that hangs up is an error to report, not a reason to die
  using namespace poet;

  CLI::App app{"Ask a running poet-coordinator's status socket what its run is doing"};
  app.fallthrough();  // --address and --json may come after the command
  app.require_subcommand(1);
  std::string address;
  app.add_option("--address", address,
                 std::string("The coordinator's status socket HOST:PORT (default: $") + kAddressVariable +
                     " if set, else " + poet::kCoordinatorStatusAddress + ")");
  bool json = false;
  app.add_flag("--json", json, "Print the server's JSON as it came (/metrics is always text)");
  add_fingerprint_flag(app);

  int pair_id = 0;
  int64_t since = 0;
  int64_t limit = kMaxEventsPerPage;
  auto* status = app.add_subcommand("status", "The run at a glance: iteration, pairs, workers, throughput");
  auto* pairs = app.add_subcommand("pairs", "Every pair: environment, scores, lineage in brief");
  auto* pair = app.add_subcommand("pair", "One pair: its scores over iterations and its lineage");
  pair->add_option("id", pair_id, "The pair's id")->required()->check(CLI::Range(0, 999'999'999));
  auto* archive = app.add_subcommand("archive", "Every environment ever admitted");
  auto* workers = app.add_subcommand("workers", "The connected workers");
  auto* events = app.add_subcommand("events", "The run's events (events.jsonl), from line --since");
  events->add_option("--since", since, "The first line (0-based; default 0)")
      ->check(CLI::Range(int64_t{0}, int64_t{1} << 50));
  events->add_option("--limit", limit, "At most this many events")->check(CLI::Range(int64_t{1}, kMaxEventsPerPage));
  auto* metrics = app.add_subcommand("metrics", "The Prometheus metrics, as text");
  std::string key_dir;
  std::string key_name;
  bool authorize = false;
  auto* keygen = app.add_subcommand(
      "keygen", "Make a CURVE key pair DIR/NAME.key and DIR/NAME.key_secret, for --curve-keys (no socket involved)");
  keygen->add_option("dir", key_dir, "The key directory (created if missing)")->required();
  keygen->add_option("name", key_name, "coordinator, or worker")
      ->required()
      ->check(CLI::IsMember({"coordinator", "worker"}));
  keygen->add_flag("--authorize", authorize, "Also copy the public key into DIR/authorized/ (workers only)");
  std::string picture_kind_name, picture_out, picture_run_dir;
  int picture_pair = -1;
  auto* picture = app.add_subcommand(
      "picture",
      "A picture of the run: scores, levels, tree, rose (.png/.svg) or a pair's course, filmstrip (.png/.svg) "
      "or walk (.gif); from the live coordinator, or from a run directory's files with --run-dir");
  picture->add_option("kind", picture_kind_name, "scores, levels, tree, rose, course, filmstrip or walk")->required();
  picture->add_option("out", picture_out, "The file to write: .png, .svg or .gif")->required();
  picture->add_option("--pair", picture_pair, "The pair (course, filmstrip, walk)")->check(CLI::Range(0, 999'999'999));
  picture->add_option("--run-dir", picture_run_dir, "Draw from this run directory's files instead (never changed)");
  if (const std::optional<int> code = parse_command_line(app, argc, argv)) return *code;
  if (keygen->parsed()) return make_keys(key_dir, key_name, authorize);
  std::optional<PictureRequest> picture_request_made;
  if (picture->parsed()) {
    Expected<PictureRequest> request = picture_request(picture_kind_name, picture_out, picture_pair);
    if (!request) {
      std::fprintf(stderr, "poetctl picture: %s\n", request.error().c_str());
      return kExitUsage;
    }
    if (!picture_run_dir.empty()) return picture_from_files(picture_run_dir, *request, picture_out);
    picture_request_made = *request;
  }

  if (address.empty()) {
    const char* from_environment = std::getenv(kAddressVariable);
    address = from_environment && *from_environment ? from_environment : poet::kCoordinatorStatusAddress;
  }

  Command command;
  if (status->parsed()) command = {"/status", printer(&print_status, "/status"), nullptr};
  if (pairs->parsed()) command = {"/pairs", printer(&print_pairs, "/pairs"), nullptr};
  if (pair->parsed()) {
    const std::string path = "/pairs/" + std::to_string(pair_id);
    command = {path, printer(&print_pair, path), nullptr};
  }
  if (archive->parsed()) command = {"/archive", printer(&print_archive, "/archive"), nullptr};
  if (workers->parsed()) command = {"/workers", printer(&print_workers, "/workers"), nullptr};
  if (events->parsed()) {
    const std::string path = "/events?since=" + std::to_string(since) + "&limit=" + std::to_string(limit);
    command = {path, printer(&print_events, "/events"), nullptr};
  }
  if (metrics->parsed()) command = {"/metrics", nullptr, nullptr};
  if (picture_request_made) {
    command.path = picture_path(picture_kind_name, picture_out, *picture_request_made);
    command.save = [&](const std::string& body) {
      if (std::string error = write_bytes(picture_out, body); !error.empty()) {
        std::fprintf(stderr, "poetctl picture: %s\n", error.c_str());
        return kExitUnreachable;
      }
      std::printf("%s: %zu bytes from %s\n", picture_out.c_str(), body.size(), command.path.c_str());
      return 0;
    };
  }
  return run(address, command, json);
}
