// poetctl: asks a running poet-coordinator's status socket what its run is doing.
//   poetctl [--address HOST:PORT] [--json] status | pairs | pair ID | archive | workers | events [--since N]
//           [--limit M] | metrics
//   poetctl keygen DIR coordinator|worker [--authorize]
//   poetctl picture KIND OUT [--pair ID] [--run-dir DIR]   a picture of the live run, or of a run directory's files
//   poetctl pack RUN_DIR FILE | unpack FILE DIR           a run as one file, to move it between machines
//   poetctl stop RUN_DIR --at-boundary      the run's coordinator stops at its next iteration boundary, exit 3
// Prints a table for people, or with --json the server's JSON as it came (/metrics is always its text); whatever
// the server sent is printed with its control characters written out (\u001b), so that it cannot drive the
// terminal. Each request has a deadline for the whole answer and a cap on its size (status_request.h). The
// address is --address, else $POET_STATUS, else 127.0.0.1:8580. Exit codes: 0 done, 1 the coordinator cannot be
// reached, answered with an error or with something else than asked (the message names the address), 2 bad
// command line or address.

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>

#include "common/program/tool_flags.h"
#include "common/protocol/status_defaults.h"
#include "common/text/utf8.h"
#include "status.pb.h"
#include "tools/poetctl_exit.h"
#include "tools/poetctl_keygen.h"
#include "tools/poetctl_pack.h"
#include "tools/poetctl_pictures.h"
#include "tools/poetctl_stop.h"
#include "tools/status_client/status_request.h"
#include "tools/status_client/status_tables.h"

namespace poet {
namespace {

constexpr char kAddressVariable[] = "POET_STATUS";

template <class Message>
std::optional<Message> parse(const std::string& body, const std::string& what) {
  std::optional<Message> message = parse_status_json<Message>(body);
  if (!message) std::fprintf(stderr, "poetctl: %s: the answer is not the JSON expected\n", what.c_str());
  return message;
}

struct Command {
  std::string path;                                     // with its query
  std::function<bool(const std::string& body)> print;   // false: the body could not be read
  std::function<int(const StatusAnswer& answer)> save;  // instead of printing: keeps the body (an exit code)
  StatusLimits limits = kStatusTextLimits;
};

// An error the server wrote, as it may be shown: printable, and no longer than a screenful.
std::string server_text(const std::string& text) {
  constexpr size_t kShown = 2000;
  return printable_text(text.substr(0, kShown)) + (text.size() > kShown ? "..." : "");
}

int run(const std::string& address, const Command& command, bool json) {
  const Expected<HostPort> where = parse_host_port(address);
  if (!where) {
    std::fprintf(stderr, "poetctl: %s\n", where.error().c_str());
    return kExitUsage;
  }
  const Expected<StatusAnswer> answer = status_get(*where, command.path, command.limits);
  const std::string what = "GET http://" + address + command.path;
  if (!answer) {
    std::fprintf(stderr, "poetctl: %s: %s\n", what.c_str(), answer.error().c_str());
    return kExitUnreachable;
  }
  if (answer->status != 200) {
    std::string message = answer->body;
    if (auto error = parse_status_json<status::Error>(answer->body); error && !error->error().empty())
      message = error->error();
    std::fprintf(stderr, "poetctl: %s: %d %s\n", what.c_str(), answer->status, server_text(message).c_str());
    return kExitUnreachable;
  }
  if (command.save) return command.save(*answer);
  if (json || !command.print) {
    const std::string printable = printable_text(answer->body);
    std::fwrite(printable.data(), 1, printable.size(), stdout);
    return 0;
  }
  return command.print(answer->body) ? 0 : kExitUnreachable;
}

template <class Message>
std::function<bool(const std::string&)> printer(void (*print)(const Message&), const std::string& what) {
  return [print, what](const std::string& body) {
    const std::optional<Message> message = parse<Message>(body, what);
    if (message) print(*message);
    return message.has_value();
  };
}

// poetctl's command line: the subcommand given, and what the options bound.
struct Options {
  std::string command;  // the subcommand's name
  std::string address;
  bool json = false;
  int pair_id = 0;
  int64_t since = 0;
  int64_t limit = kMaxEventsPerPage;
  std::string key_dir, key_name;
  bool authorize = false;
  std::string picture_kind_name, picture_out, picture_run_dir;
  int picture_pair = -1;
  std::string pack_dir, pack_file;
  std::string stop_dir;
  bool at_boundary = false;
};

// The subcommands that ask the status socket.
void add_status_commands(CLI::App& app, Options& o) {
  app.add_subcommand("status", "The run at a glance: iteration, pairs, workers, throughput");
  app.add_subcommand("pairs", "Every pair: environment, scores, lineage in brief");
  auto* pair = app.add_subcommand("pair", "One pair: its scores over iterations and its lineage");
  pair->add_option("id", o.pair_id, "The pair's id")->required()->check(CLI::Range(0, 999'999'999));
  app.add_subcommand("archive", "Every environment ever admitted");
  app.add_subcommand("workers", "The connected workers");
  auto* events = app.add_subcommand("events", "The run's events (events.jsonl), from line --since");
  events->add_option("--since", o.since, "The first line (0-based; default 0)")
      ->check(CLI::Range(int64_t{0}, int64_t{1} << 50));
  events->add_option("--limit", o.limit, "At most this many events")
      ->capture_default_str()
      ->check(CLI::Range(int64_t{1}, kMaxEventsPerPage));
  app.add_subcommand("metrics", "The Prometheus metrics, as text");
}

void add_keygen_command(CLI::App& app, Options& o) {
  auto* keygen = app.add_subcommand(
      "keygen", "Make a CURVE key pair DIR/NAME.key and DIR/NAME.key_secret, for --curve-keys (no socket involved)");
  keygen->add_option("dir", o.key_dir, "The key directory (created if missing)")->required();
  keygen->add_option("name", o.key_name, "coordinator, or worker")
      ->required()
      ->check(CLI::IsMember({"coordinator", "worker"}));
  keygen->add_flag("--authorize", o.authorize, "Also copy the public key into DIR/authorized/ (workers only)");
}

void add_picture_command(CLI::App& app, Options& o) {
  auto* picture = app.add_subcommand(
      "picture",
      "A picture of the run: scores, levels, annecs, tree, rose (.png/.svg) or a pair's course, filmstrip, lineage "
      "(.png/.svg) or walk (.gif); from the live coordinator, or from a run directory's files with --run-dir");
  picture
      ->add_option("kind", o.picture_kind_name,
                   "scores, levels, annecs, tree, rose, course, filmstrip, lineage or walk")
      ->required();
  picture->add_option("out", o.picture_out, "The file to write: .png, .svg or .gif")->required();
  picture
      ->add_option("--pair", o.picture_pair, "The pair, which course, filmstrip, lineage and walk need (default: none)")
      ->check(CLI::Range(0, 999'999'999));
  picture->add_option(
      "--run-dir", o.picture_run_dir,
      "Draw from this run directory's files (never changed) instead of the live coordinator (default: none)");
}

void add_pack_commands(CLI::App& app, Options& o) {
  auto* pack = app.add_subcommand(
      "pack",
      "Write RUN_DIR's run (its last checkpoint and the logs it has seen; the run may be going on) into one "
      "file, to go on elsewhere with poet-coordinator --resume --from-pack (no socket involved)");
  pack->add_option("run_dir", o.pack_dir, "The run directory")->required();
  pack->add_option("file", o.pack_file, "The pack to write (replaced if it exists)")->required();
  auto* unpack = app.add_subcommand(
      "unpack",
      "Restore a pack into DIR (new or empty) without running it: read it with poet-report, or go on with "
      "poet-coordinator --run-dir DIR --resume");
  unpack->add_option("file", o.pack_file, "The pack")->required();
  unpack->add_option("dir", o.pack_dir, "The run directory to make")->required();
}

void add_stop_command(CLI::App& app, Options& o) {
  auto* stop = app.add_subcommand(
      "stop",
      "Ask the coordinator of RUN_DIR to stop at its next iteration boundary: the iteration in flight finished and "
      "checkpointed, exit code 3 (a request file in RUN_DIR, so any machine that sees it can ask; no socket "
      "involved). An immediate stop is SIGINT or SIGTERM to the coordinator");
  stop->add_option("run_dir", o.stop_dir, "The run directory")->required();
  stop->add_flag("--at-boundary", o.at_boundary, "Stop at the next iteration boundary (the only stop asked this way)")
      ->required();
}

// Parses the command line into `o`. nullopt: go on; otherwise the exit code (as parse_command_line).
std::optional<int> parse_options(int argc, char** argv, Options& o) {
  CLI::App app{"Ask a running poet-coordinator's status socket what its run is doing"};
  app.fallthrough();  // --address and --json may come after the command
  app.require_subcommand(1);
  app.add_option("--address", o.address,
                 std::string("The coordinator's status socket HOST:PORT (default: $") + kAddressVariable +
                     " if set, else " + poet::kCoordinatorStatusAddress + ")");
  app.add_flag("--json", o.json, "Print the server's JSON as it came (/metrics is always text)");
  add_fingerprint_flag(app);
  add_status_commands(app, o);
  add_keygen_command(app, o);
  add_picture_command(app, o);
  add_pack_commands(app, o);
  add_stop_command(app, o);
  if (std::optional<int> code = parse_command_line(app, argc, argv)) return code;
  o.command = app.get_subcommands().front()->get_name();  // exactly one, as required
  return std::nullopt;
}

// The request of a status subcommand, and the table its answer prints as.
Command status_command(const Options& o) {
  if (o.command == "status") return {"/status", printer(&print_status, "/status"), nullptr};
  if (o.command == "pairs") return {"/pairs", printer(&print_pairs, "/pairs"), nullptr};
  if (o.command == "pair") {
    const std::string path = "/pairs/" + std::to_string(o.pair_id);
    return {path, printer(&print_pair, path), nullptr};
  }
  if (o.command == "archive") return {"/archive", printer(&print_archive, "/archive"), nullptr};
  if (o.command == "workers") return {"/workers", printer(&print_workers, "/workers"), nullptr};
  if (o.command == "events") {
    const std::string path = "/events?since=" + std::to_string(o.since) + "&limit=" + std::to_string(o.limit);
    return {path, printer(&print_events, "/events"), nullptr};
  }
  return {"/metrics", nullptr, nullptr};
}

// --address, else $POET_STATUS, else the default.
std::string status_address(const std::string& address) {
  if (!address.empty()) return address;
  const char* from_environment = std::getenv(kAddressVariable);
  return from_environment && *from_environment ? from_environment : poet::kCoordinatorStatusAddress;
}

}  // namespace
}  // namespace poet

int run_tool(int argc, char** argv) {
  using namespace poet;

  Options o;
  if (const std::optional<int> code = parse_options(argc, argv, o)) return *code;
  if (o.command == "keygen") return make_keys(o.key_dir, o.key_name, o.authorize);
  if (o.command == "pack") return pack_run(o.pack_dir, o.pack_file);
  if (o.command == "unpack") return unpack_run(o.pack_file, o.pack_dir);
  if (o.command == "stop") return stop_at_boundary(o.stop_dir);
  if (o.command != "picture") return run(status_address(o.address), status_command(o), o.json);

  Expected<PictureRequest> request = picture_request(o.picture_kind_name, o.picture_out, o.picture_pair);
  if (!request) {
    std::fprintf(stderr, "poetctl picture: %s\n", request.error().c_str());
    return kExitUsage;
  }
  if (!o.picture_run_dir.empty()) return picture_from_files(o.picture_run_dir, *request, o.picture_out);
  Command command;
  command.path = picture_path(o.picture_kind_name, o.picture_out, *request);
  command.limits = kStatusPictureLimits;
  command.save = [&](const StatusAnswer& answer) {
    return save_picture(o.picture_out, answer, command.path, request->encoding);
  };
  return run(status_address(o.address), command, o.json);
}

int main(int argc, char** argv) {
  std::signal(SIGPIPE, SIG_IGN);  // a server that hangs up is an error to report, not a reason to die
  return poet::output_checked("poetctl", run_tool(argc, argv));
}
