// poetctl: asks a running poet-coordinator's status socket what its run is doing.
//   poetctl [--address HOST:PORT] [--json] status | pairs | pair ID | archive | workers | events [--since N]
//           [--limit M] | metrics
//   poetctl keygen DIR coordinator|worker [--authorize]
//   poetctl picture KIND OUT [--pair ID] [--run-dir DIR]   a picture of the live run, or of a run directory's files
//   poetctl pack RUN_DIR FILE | unpack FILE DIR           a run as one file, to move it between machines
// Prints a table for people, or with --json the server's JSON as it came (/metrics is always its text). The
// address is --address, else $POET_STATUS, else 127.0.0.1:8580. Exit codes: 0 done, 1 the coordinator cannot be
// reached or answered with an error (the message names the address), 2 bad command line or address.

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>

#include "common/tool_flags.h"
#include "coordinator/status_client/status_defaults.h"
#include "coordinator/status_client/status_request.h"
#include "coordinator/status_client/status_tables.h"
#include "poetctl_exit.h"
#include "poetctl_keygen.h"
#include "poetctl_pack.h"
#include "poetctl_pictures.h"
#include "status.pb.h"

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
  const Expected<StatusAnswer> answer = status_get(*where, command.path);
  const std::string what = "GET http://" + address + command.path;
  if (!answer) {
    std::fprintf(stderr, "poetctl: cannot reach the coordinator at %s: %s\n", address.c_str(), answer.error().c_str());
    return kExitUnreachable;
  }
  if (answer->status != 200) {
    std::string message = answer->body;
    if (auto error = parse<status::Error>(answer->body, what); error && !error->error().empty())
      message = error->error();
    std::fprintf(stderr, "poetctl: %s: %d %s\n", what.c_str(), answer->status, message.c_str());
    return kExitUnreachable;
  }
  if (command.save) return command.save(answer->body);
  if (json || !command.print) {
    std::fwrite(answer->body.data(), 1, answer->body.size(), stdout);
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
      "A picture of the run: scores, levels, annecs, tree, rose (.png/.svg) or a pair's course, filmstrip, lineage "
      "(.png/.svg) or walk (.gif); from the live coordinator, or from a run directory's files with --run-dir");
  picture
      ->add_option("kind", picture_kind_name, "scores, levels, annecs, tree, rose, course, filmstrip, lineage or walk")
      ->required();
  picture->add_option("out", picture_out, "The file to write: .png, .svg or .gif")->required();
  picture->add_option("--pair", picture_pair, "The pair (course, filmstrip, lineage, walk)")
      ->check(CLI::Range(0, 999'999'999));
  picture->add_option("--run-dir", picture_run_dir, "Draw from this run directory's files instead (never changed)");
  std::string pack_dir, pack_file;
  auto* pack = app.add_subcommand(
      "pack",
      "Write RUN_DIR's run (its last checkpoint and the logs it has seen; the run may be going on) into one "
      "file, to go on elsewhere with poet-coordinator --resume --from-pack (no socket involved)");
  pack->add_option("run_dir", pack_dir, "The run directory")->required();
  pack->add_option("file", pack_file, "The pack to write (replaced if it exists)")->required();
  auto* unpack = app.add_subcommand(
      "unpack",
      "Restore a pack into DIR (new or empty) without running it: read it with poet-report, or go on with "
      "poet-coordinator --run-dir DIR --resume");
  unpack->add_option("file", pack_file, "The pack")->required();
  unpack->add_option("dir", pack_dir, "The run directory to make")->required();
  if (const std::optional<int> code = parse_command_line(app, argc, argv)) return *code;
  if (keygen->parsed()) return make_keys(key_dir, key_name, authorize);
  if (pack->parsed()) return pack_run(pack_dir, pack_file);
  if (unpack->parsed()) return unpack_run(pack_file, pack_dir);
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
    command.save = [&](const std::string& body) { return save_picture(picture_out, body, command.path); };
  }
  return run(address, command, json);
}
