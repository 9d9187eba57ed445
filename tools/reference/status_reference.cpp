#include "tools/reference/status_reference.h"

#include <google/protobuf/dynamic_message.h>
#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <cctype>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <stdexcept>
#include <vector>

#include "common/plumbing/text_file.h"
#include "coordinator/status/metric_families.h"
#include "coordinator/status/run_picture_cache.h"
#include "coordinator/status/status_server.h"
#include "proto/schema_comments.h"
#include "status.pb.h"

namespace poet {
namespace {

namespace protobuf = google::protobuf;

constexpr std::string_view kPackage = "poet.status.";

std::string str(std::string_view text) { return std::string(text); }

// Text for a Markdown table cell: a pipe would end the cell, a line end the row.
std::string cell(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += '\\';
    out += c == '\n' ? ' ' : c;
  }
  return out.empty() ? "—" : out;
}

std::string code(std::string_view text) { return "`" + str(text) + "`"; }

bool in_package(const protobuf::Descriptor& message) { return message.full_name().rfind(str(kPackage), 0) == 0; }

// A field's type as the page writes it: the .proto type, what JSON makes of a 64-bit integer, a link to a nested
// message of status.proto.
std::string type_text(const protobuf::FieldDescriptor& field) {
  auto one = [](const protobuf::FieldDescriptor& f) -> std::string {
    switch (f.cpp_type()) {
      case protobuf::FieldDescriptor::CPPTYPE_INT64:
      case protobuf::FieldDescriptor::CPPTYPE_UINT64:
        return code(f.type_name()) + " (a JSON string)";
      case protobuf::FieldDescriptor::CPPTYPE_MESSAGE: {
        const protobuf::Descriptor& m = *f.message_type();
        if (in_package(m)) return "[" + m.name() + "](#" + heading_slug(m.name()) + ")";
        if (m.full_name() == "google.protobuf.Struct") return "JSON object";
        return code(m.full_name()) + " (" + m.file()->name() + ")";
      }
      default:
        return code(f.type_name());
    }
  };
  if (field.is_map()) {
    const protobuf::Descriptor& entry = *field.message_type();
    return "map: " + one(*entry.map_key()) + " → " + one(*entry.map_value());
  }
  if (field.is_repeated()) return "list of " + one(field);
  return one(field);
}

// A page that cannot be made: a message without an example, a field without a comment.
struct PageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The message's comment, then a table of its fields with their meanings (each field must have one).
void message_table(std::string& out, const protobuf::Descriptor& message) {
  const std::string about = schema_comment(message);
  if (about.empty()) throw PageError("proto/status.proto: " + message.full_name() + " has no comment");
  out += about + "\n\n| Field | Type | Meaning |\n|---|---|---|\n";
  for (int i = 0; i < message.field_count(); ++i) {
    const protobuf::FieldDescriptor& field = *message.field(i);
    const std::string meaning = schema_comment(field);
    if (meaning.empty()) throw PageError("proto/status.proto: " + field.full_name() + " has no comment");
    out += "| " + code(field.name()) + " | " + type_text(field) + " | " + cell(meaning) + " |\n";
  }
  out += "\n";
}

// status.proto's messages a message holds, directly or further down, in the order first met (map entries and other
// files' messages left out).
void nested_messages(const protobuf::Descriptor& message, std::vector<const protobuf::Descriptor*>& found) {
  for (int i = 0; i < message.field_count(); ++i) {
    const protobuf::FieldDescriptor& field = *message.field(i);
    if (field.cpp_type() != protobuf::FieldDescriptor::CPPTYPE_MESSAGE || field.is_map()) continue;
    const protobuf::Descriptor* inner = field.message_type();
    if (!in_package(*inner) || std::find(found.begin(), found.end(), inner) != found.end()) continue;
    found.push_back(inner);
    nested_messages(*inner, found);
  }
}

// A message of status.proto from the embedded descriptor set (the one with comments).
const protobuf::Descriptor& message_of(std::string_view name) {
  const protobuf::Descriptor* message = schema_message(str(kPackage) + str(name));
  if (message == nullptr) throw PageError("the embedded schema has no message " + str(kPackage) + str(name));
  return *message;
}

void errors_table(std::string& out, std::span<const RouteError> own) {
  std::vector<RouteError> errors(own.begin(), own.end());
  errors.insert(errors.end(), std::begin(kEveryRouteErrors), std::end(kEveryRouteErrors));
  std::stable_sort(errors.begin(), errors.end(),
                   [](const RouteError& a, const RouteError& b) { return a.status < b.status; });
  out += "| Status | When |\n|---|---|\n";
  for (const RouteError& error : errors) out += "| " + std::to_string(error.status) + " | " + cell(error.when) + " |\n";
  out += "\n";
}

void parameters(std::string& out, const StatusRoute& route) {
  if (!route.path_params.empty()) {
    out += "Path parameters:\n\n| Name | Values | Meaning |\n|---|---|---|\n";
    for (const PathParam& param : route.path_params) {
      std::string values;
      for (std::string_view value : param.values) values += (values.empty() ? "" : ", ") + code(value);
      out += "| " + code("{" + str(param.name) + "}") + " | " + (values.empty() ? cell(kPairIdRule) : values) + " | " +
             cell(param.meaning) + " |\n";
    }
    out += "\n";
  }
  if (!route.query_params.empty()) {
    out +=
        "Query parameters (whole numbers; a parameter not listed is ignored):\n\n"
        "| Name | Bounds | Default | Meaning |\n|---|---|---|---|\n";
    for (const QueryParam& param : route.query_params)
      out += "| " + code(param.name) + " | " + std::to_string(param.lo) + " to " + std::to_string(param.hi) + " | " +
             std::to_string(param.fallback) + " | " + cell(param.meaning) + " |\n";
    out += "\n";
  }
}

// The route's example answer from a real run: a JSON body or the /metrics lines as they came, else the status line,
// content type and size of the answer.
void example_text(std::string& out, const StatusRoute& route, const RouteExamples& examples) {
  const auto example = examples.find(str(route.title));
  if (example == examples.end())
    throw PageError("no example answer of " + str(route.pattern) + " (" + example_file(route) + ")");
  const std::string request = "`GET " + str(route.example_path) + "`";
  const std::string file = "docs/reference/examples/" + example_file(route);
  std::string text = example->second;
  if (!text.ends_with('\n')) text += '\n';
  if (route.content_type == kJsonType || route.kind == RouteKind::kMetrics) {
    out += "An answer of " + request + (route.kind == RouteKind::kMetrics ? ", some of its lines" : "") + " (" + file +
           "):\n\n```" + (route.content_type == kJsonType ? "json" : "text") + "\n" + text + "```\n\n";
  } else {
    text.pop_back();
    out += "An answer of " + request + ": " + code(text) + " (" + file + ").\n\n";
  }
}

void route_section(std::string& out, const StatusRoute& route, const RouteExamples& examples) {
  out += "## " + str(route.title) + "\n\n";
  out += code("GET " + str(route.pattern)) + " — " + str(route.summary) + "\n\n";
  parameters(out, route);
  out += "Content type: " + code(route.content_type) + ".";
  if (!route.message.empty()) out += " The body is the message " + code(route.message) + ".";
  out += "\n\n";
  if (!route.body.empty()) out += str(route.body) + "\n\n";
  if (!route.message.empty()) message_table(out, message_of(route.message));
  example_text(out, route, examples);
  out += "Errors:\n\n";
  errors_table(out, route.errors);
}

void http_intro(std::string& out) {
  out +=
      "# HTTP routes\n\n"
      "<!-- Generated by `poet-reference http` from coordinator/status/status_route_table.h, proto/status.proto "
      "and docs/reference/examples/; do not edit. -->\n\n"
      "The coordinator serves its state over HTTP/1.1 on the status socket: the run, its pairs, its workers, its "
      "events, Prometheus metrics, pictures and a dashboard. Nothing a client does changes the run. `poetctl` "
      "reads the same routes.\n\n";
  out += "| Route | Request | Answer |\n|---|---|---|\n";
  for (const StatusRoute& route : kStatusRoutes)
    out += "| [" + str(route.title) + "](#" + heading_slug(route.title) + ") | " + code("GET " + str(route.pattern)) +
           " | " + (route.message.empty() ? code(route.content_type) : code(route.message)) + " |\n";
  out +=
      "\n## The socket\n\n"
      "`poet-coordinator --status-address HOST:PORT` chooses where it listens: " +
      code(kCoordinatorStatusAddress) +
      " unless told otherwise, port 0 for any free port (the log says which: `status: http://HOST:PORT/status`), "
      "an empty address for no socket. `--health-address HOST:PORT` starts a second listener that answers "
      "[`/healthz`](#health) alone, and 404 to every other path, so that probes never wait behind the status "
      "socket's slow answers (pictures, replays).\n\n"
      "Every route answers GET and HEAD (HEAD is GET without the body); another method gets a 405 with "
      "`Allow: GET, HEAD`. Every answer carries `Cache-Control: no-store`.\n\n"
      "## JSON\n\n"
      "The JSON bodies are proto/status.proto's messages in protobuf's JSON mapping, on one line: the field names "
      "as written in the .proto file (`pairs_active`, not `pairsActive`), every scalar, list and map field printed "
      "even when zero or empty, a nested message absent until the coordinator has one to show. 64-bit integers "
      "(`int64`, `uint64`) are JSON strings (`\"rollouts\": \"123456\"`), since a JSON number loses precision "
      "beyond 2^53; 32-bit integers and doubles are JSON numbers. An absent pair id or iteration is -1.\n\n"
      "The example answers below, one for each route, are a real run's, `poet-coordinator --config "
      "deploy/configs/quick.textproto --run-dir out/quick-capture --local-workers 2 --start-from "
      "data/walkers/flat-walker.json --iterations 6 --status-address 127.0.0.1:0`, taken at iteration 5 by "
      "`python3 docs/reference/examples/capture.py 127.0.0.1:PORT --at-iteration 5` (PORT from the log's `status:` "
      "line), the one way to refresh them: it indents the JSON answers and cuts their lists to three entries, keeps "
      "a few families' lines of `/metrics`, and of the dashboard and the pictures writes the status, content type "
      "and size of the answer. The tests parse each JSON answer into its message, refusing any field the schema "
      "lacks and requiring every scalar, list and map field it has; check the episode's keys, that each line of "
      "`/metrics` is of a declared family, and each size line the route's content type.\n\n"
      "## Errors\n\n"
      "Every error has a JSON body, the message `Error`:\n\n";
  message_table(out, message_of("Error"));
  out +=
      "Beyond each route's own errors (listed with it), the socket answers:\n\n"
      "| Status | When |\n|---|---|\n"
      "| 400 | a query with more than " +
      std::to_string(kMaxQueryParams) +
      " parameters |\n"
      "| 404 | a path that is no route (the body lists the routes) |\n"
      "| 405 | a method other than GET or HEAD on a route |\n"
      "| 413 | a request body of more than " +
      std::to_string(StatusServerOptions{}.payload_max_bytes) +
      " bytes (no route reads a body) |\n"
      "| 414 | a request URI of more than " +
      std::to_string(kMaxUriBytes) +
      " bytes |\n"
      "| 500 | the coordinator failed to make the answer |\n\n"
      "Paths match exactly: no trailing slash, lower case as written, a pair id in decimal without a sign or "
      "leading zero.\n\n";
}

struct GroupText {
  MetricGroup group;
  std::string_view title;
  std::string_view about;
};
constexpr GroupText kGroups[] = {
    {MetricGroup::kRun, "Run",
     "The run as the run loop last published it: at start and after each iteration. The rollout and step counters "
     "are the checkpoint's, so they go on from where a resumed run stopped."},
    {MetricGroup::kDispatch, "Workers and dispatch",
     "The dispatcher's workers, queue and counts since this coordinator started; all 0 with the local evaluator "
     "(no `--listen`)."},
    {MetricGroup::kVerification, "Verification and trust",
     "What the dispatcher found of the workers' answers, and of the CURVE keys, since this coordinator started."},
    {MetricGroup::kCoordinator, "Cache and phases",
     "The coordinator's own work: the score cache since it started, and where its time went as of its last "
     "checkpoint."},
};

std::string labels_text(const MetricFamily& family) {
  std::string out;
  for (const MetricLabel& label : family.labels) {
    std::string values;
    for (std::string_view value : label.values) values += (values.empty() ? "" : ", ") + code(value);
    out += (out.empty() ? "" : "; ") + code(label.name) + ": " + values;
  }
  return out;
}

// A question, and the PromQL that answers it over the declared names (metric_family: a name not in the table does
// not compile).
struct PromqlExample {
  std::string_view question;
  std::string query;
};

std::vector<PromqlExample> promql_examples() {
  auto n = [](const MetricFamily& family) { return str(family.name); };
  return {
      {"Environment steps per second, over the last 5 minutes",
       "rate(" + n(metric_family("poet_env_steps_total")) + "[5m])"},
      {"How far the run is, from 0 to 1",
       n(metric_family("poet_iteration")) + " / " + n(metric_family("poet_iterations_limit"))},
      {"ANNECS, counted at admission", n(metric_family("poet_annecs")) + "{definition=\"at_admission\"}"},
      {"The hardest stumps solved so far",
       n(metric_family("poet_obstacle_frontier")) + "{measure=\"stump_hi\", among=\"solved\"}"},
      {"Jobs wait and no worker is connected (an alert)",
       n(metric_family("poet_queue_depth")) + " > 0 and " + n(metric_family("poet_workers")) + " == 0"},
      {"Frames dropped in the last hour, by reason",
       "sum by (reason) (increase(" + n(metric_family("poet_dropped_frames_total")) + "[1h]))"},
      {"A worker was refused for wrong results in the last hour (an alert)",
       "increase(" + n(metric_family("poet_wrong_workers_total")) + "[1h]) > 0"},
      {"The share of the iterations' time spent waiting for rollouts",
       n(metric_family("poet_waiting_seconds_total")) + " / sum without (phase) (" +
           n(metric_family("poet_phase_seconds_total")) + ")"},
      {"The share of episodes the score cache answered, over the last hour",
       "rate(" + n(metric_family("poet_cached_episodes_total")) + "[1h]) / rate(" +
           n(metric_family("poet_rollouts_total")) + "[1h])"},
  };
}

}  // namespace

std::string heading_slug(std::string_view heading) {
  std::string kept;
  for (unsigned char c : heading)
    if (std::isalnum(c) || c == '_' || c == '-' || std::isspace(c)) kept += static_cast<char>(std::tolower(c));
  const size_t first = kept.find_first_not_of(" \t\n");
  const size_t last = kept.find_last_not_of(" \t\n");
  if (first == std::string::npos) return "";
  std::string slug;
  bool separator = false;
  for (char c : kept.substr(first, last - first + 1)) {
    if (c == '-' || std::isspace(static_cast<unsigned char>(c))) {
      separator = true;
      continue;
    }
    if (separator) slug += '-';
    separator = false;
    slug += c;
  }
  return slug;
}

std::string example_file(const StatusRoute& route) {
  return heading_slug(route.title) + (route.content_type == kJsonType ? ".json" : ".txt");
}

namespace {

// Why the JSON lacks a field protobuf's JSON prints even at zero: every scalar, list and map field of the message
// without presence (a message field, an `optional` one or a oneof's is printed only when set), and the same of each
// nested status.proto message it holds. nullopt when none is missing.
std::optional<std::string> missing_field(const protobuf::Descriptor& message, const nlohmann::json& value,
                                         const std::string& where) {
  if (!value.is_object()) return std::nullopt;  // the strict parse checked the types
  for (int i = 0; i < message.field_count(); ++i) {
    const protobuf::FieldDescriptor& field = *message.field(i);
    const std::string at = where + "." + field.name();
    const auto found = value.find(field.name());
    const bool nested = field.cpp_type() == protobuf::FieldDescriptor::CPPTYPE_MESSAGE && !field.is_map() &&
                        in_package(*field.message_type());
    if (found == value.end()) {
      if (field.has_presence()) continue;
      return at + " is missing (every scalar, list and map field is printed; capture the examples again)";
    }
    if (!nested) continue;
    if (field.is_repeated()) {
      for (const nlohmann::json& entry : *found)
        if (auto missing = missing_field(*field.message_type(), entry, at + "[]")) return missing;
    } else if (auto missing = missing_field(*field.message_type(), *found, at)) {
      return missing;
    }
  }
  return std::nullopt;
}

std::optional<std::string> message_problem(const StatusRoute& route, const std::string& json) {
  // the generated schema's pool, reached through one of its messages so that status.pb.cc is linked in
  const protobuf::Descriptor* descriptor =
      status::Error::descriptor()->file()->pool()->FindMessageTypeByName(str(kPackage) + str(route.message));
  if (descriptor == nullptr) return "the schema has no message " + str(route.message);
  const std::unique_ptr<protobuf::Message> message(
      protobuf::MessageFactory::generated_factory()->GetPrototype(descriptor)->New());
  protobuf::util::JsonParseOptions strict;
  strict.ignore_unknown_fields = false;
  const auto parsed = protobuf::util::JsonStringToMessage(json, message.get(), strict);
  if (!parsed.ok()) return "not a " + str(route.message) + ": " + parsed.ToString();
  return missing_field(*descriptor, nlohmann::json::parse(json, nullptr, false), str(route.message));
}

// The episode: a JSON object with exactly the keys episode_json writes.
std::optional<std::string> episode_problem(const std::string& json) {
  const nlohmann::json episode = nlohmann::json::parse(json, nullptr, false);
  if (!episode.is_object()) return "not a JSON object";
  for (std::string_view key : kEpisodeKeys)
    if (!episode.contains(key)) return "no key \"" + str(key) + "\" (the episode writer writes it)";
  for (const auto& [key, value] : episode.items())
    if (std::find(std::begin(kEpisodeKeys), std::end(kEpisodeKeys), key) == std::end(kEpisodeKeys))
      return "a key \"" + key + "\" the episode writer does not write";
  return std::nullopt;
}

const MetricFamily* declared_family(std::string_view name) {
  for (const MetricFamily& family : kMetricFamilies)
    if (family.name == name) return &family;
  return nullptr;
}

// Lines of the exposition: HELP, TYPE and samples of declared families, HELP and TYPE as declared.
std::optional<std::string> metrics_problem(const std::string& text) {
  static const std::regex kHelp(R"(# HELP ([a-z_]+) (.*))");
  static const std::regex kType(R"(# TYPE ([a-z_]+) ([a-z]+))");
  static const std::regex kSample(R"(([a-z_]+)(\{[a-z_]+="[a-z_0-9]*"(,[a-z_]+="[a-z_0-9]*")*\})? -?[0-9.e+]+)");
  int samples = 0;
  size_t start = 0;
  for (int line_number = 1; start < text.size(); ++line_number) {
    const size_t end = std::min(text.find('\n', start), text.size());
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    const std::string where = "line " + std::to_string(line_number) + ": ";
    std::smatch m;
    const bool help = std::regex_match(line, m, kHelp), type = !help && std::regex_match(line, m, kType);
    const bool sample = !help && !type && std::regex_match(line, m, kSample);
    if (!help && !type && !sample) return where + "not a HELP, TYPE or sample line of the exposition";
    const MetricFamily* family = declared_family(m.str(1));
    if (family == nullptr) return where + m.str(1) + " is no family of metric_families.h";
    if (help && m.str(2) != family->help) return where + "the HELP of " + m.str(1) + " is not as declared";
    if (type && m.str(2) != family->type) return where + m.str(1) + " is a " + str(family->type);
    samples += sample;
  }
  if (samples == 0) return "no sample line";
  return std::nullopt;
}

// "200 image/svg+xml, 65,099 bytes": a 200 of the content type the route answers its example path with.
std::optional<std::string> size_problem(const StatusRoute& route, const std::string& text) {
  static const std::regex kSize(R"(200 (.+), [1-9][0-9]{0,2}(,[0-9]{3})* bytes\n?)");
  std::smatch m;
  if (!std::regex_match(text, m, kSize)) return "not a line \"200 TYPE, N bytes\"";
  std::string expected(route.content_type);
  if (route.kind == RouteKind::kRunPicture || route.kind == RouteKind::kPairPicture) {
    const std::optional<RouteMatch> match = match_route(route.example_path);
    if (!match) return str(route.example_path) + " is no path of the route";
    expected = mime_type(match->picture.encoding);
  }
  if (m.str(1) != expected) return "the content type " + m.str(1) + " is not " + expected;
  return std::nullopt;
}

}  // namespace

std::optional<std::string> example_problem(const StatusRoute& route, const std::string& text) {
  if (!route.message.empty()) return message_problem(route, text);
  if (route.kind == RouteKind::kEpisode) return episode_problem(text);
  if (route.kind == RouteKind::kMetrics) return metrics_problem(text);
  return size_problem(route, text);
}

Expected<std::string> http_reference_markdown(const RouteExamples& examples) {
  try {
    std::string out;
    http_intro(out);
    std::vector<const protobuf::Descriptor*> nested;
    for (const StatusRoute& route : kStatusRoutes) {
      route_section(out, route, examples);
      if (!route.message.empty()) nested_messages(message_of(route.message), nested);
    }
    out += "## Nested messages\n\nThe messages the answers above hold, each field with its meaning.\n\n";
    for (const protobuf::Descriptor* message : nested) {
      out += "### " + message->name() + "\n\n";
      message_table(out, *message);
    }
    out.pop_back();  // the page ends with one line end (poet-reference adds it)
    out.pop_back();
    return out;
  } catch (const PageError& e) {
    return Unexpected{e.what()};
  }
}

Expected<std::string> http_reference_page(const std::filesystem::path& examples_dir) {
  RouteExamples examples;
  for (const StatusRoute& route : kStatusRoutes) {
    const std::filesystem::path file = examples_dir / example_file(route);
    Expected<std::string> text = read_text_file(file, 1 << 20);
    if (!text) return Unexpected{file.string() + ": " + text.error()};
    if (std::optional<std::string> problem = example_problem(route, *text))
      return Unexpected{file.string() + ": " + *problem};
    examples[str(route.title)] = std::move(*text);
  }
  return http_reference_markdown(examples);
}

std::string metrics_reference_page() {
  std::string out =
      "# Metrics\n\n"
      "<!-- Generated by `poet-reference metrics` from coordinator/status/metric_families.h; do not edit. -->\n\n"
      "[`GET /metrics`](http.md#metrics) on the coordinator's status socket answers every metric below in "
      "Prometheus text format 0.0.4 (`" +
      str(kMetricsType) +
      "`), each family with its HELP and TYPE lines. Every family is there from the coordinator's start, at 0 "
      "before anything is counted, and a labelled family has a sample for each value of its labels listed here, so "
      "that a rate never starts from a missing series. A counter's name ends in `_total`.\n\n"
      "A Prometheus scrape job for a coordinator whose status socket is at 10.0.0.5:8580:\n\n"
      "```yaml\n"
      "scrape_configs:\n"
      "  - job_name: poet\n"
      "    static_configs:\n"
      "      - targets: [\"10.0.0.5:8580\"]\n"
      "```\n\n";
  for (const GroupText& group : kGroups) {
    out += "## " + str(group.title) + "\n\n" + str(group.about) + "\n\n";
    out += "| Name | Type | Labels | HELP |\n|---|---|---|---|\n";
    for (const MetricFamily& family : kMetricFamilies)
      if (family.group == group.group)
        out += "| " + code(family.name) + " | " + str(family.type) + " | " + cell(labels_text(family)) + " | " +
               cell(family.help) + " |\n";
    out += "\n";
  }
  out +=
      "## PromQL examples\n\n"
      "The names above in queries, as a Prometheus that scrapes the coordinator takes them (each sample also "
      "carries the scrape's `job` and `instance` labels). Each query is checked by `promtool test rules "
      "docs/reference/examples/promql_test.yml`, over series named and labelled as `/metrics` writes them, in the "
      "test `docs_promql` where Debian's `prometheus` package (which provides promtool) is installed; elsewhere "
      "that test is skipped. The unit tests check that every query here is in that file.\n\n"
      "| Question | PromQL |\n|---|---|\n";
  for (const PromqlExample& example : promql_examples())
    out += "| " + cell(example.question) + " | " + code(cell(example.query)) + " |\n";
  out.pop_back();  // the page ends with one line end (poet-reference adds it)
  return out;
}

}  // namespace poet
