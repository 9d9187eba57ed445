#pragma once
// The status socket's reference pages as Markdown, generated so that they cannot drift: docs/reference/http.md
// from the route table (status_route_table.h), the answers' messages of proto/status.proto with their comments
// and the example answers kept in docs/reference/examples/; docs/reference/metrics.md from the metric table
// (metric_families.h). poet-reference writes them; tests/docs/check_reference_pages.py compares them with the
// committed pages.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"
#include "coordinator/status/status_route_table.h"

namespace poet {

// The example answers, by route title ("Status"): a JSON body as a client receives it, some lines of /metrics, or
// for the dashboard and the pictures the answer's status, content type and size ("200 image/svg+xml, 65,099 bytes").
using RouteExamples = std::map<std::string, std::string>;

// The file a route's example answer is kept in, relative to the examples' folder: "<slug>.json" for a JSON answer
// ("status.json", "pair-episode.json"), "<slug>.txt" for another ("metrics.txt", "run-pictures.txt").
std::string example_file(const StatusRoute& route);

// Why this text is not an example answer of the route, or nullopt when it is one. A route with a message: the JSON
// must parse strictly into it (no unknown field, no wrong type) and hold every field protobuf's JSON prints even at
// zero (scalars, lists, maps), in it and in the nested messages it holds, so a field added to status.proto fails
// until the examples are captured again. The episode: a JSON object with exactly kEpisodeKeys. /metrics: HELP,
// TYPE and sample lines of families declared in metric_families.h, HELP and TYPE as declared. The dashboard and the
// pictures: "200 TYPE, N bytes" with the content type the route answers its example path with.
std::optional<std::string> example_problem(const StatusRoute& route, const std::string& text);

// docs/reference/http.md: the socket, its JSON and its errors, then each route of kStatusRoutes — method, path,
// parameters with their bounds, content type, the answer's message with each field's meaning (its comment in
// proto/status.proto, from the embedded descriptor set: proto/schema_comments.h), an example answer, the errors —
// then the messages the answers hold. `examples` must have one for each route. Errors: a missing
// example, or a message or field of status.proto without a comment (the page would leave its meaning out).
Expected<std::string> http_reference_markdown(const RouteExamples& examples);

// The same page with the examples read from `examples_dir` (docs/reference/examples): each file is checked with
// example_problem, and one that is missing or off the schema is an error naming it.
Expected<std::string> http_reference_page(const std::filesystem::path& examples_dir);

// docs/reference/metrics.md: every family of kMetricFamilies by group — name, type, labels with their values,
// HELP — and PromQL examples over those names.
std::string metrics_reference_page();

// A heading's anchor as MkDocs makes it: lower case, punctuation dropped, spaces to hyphens ("Pair episode" →
// "pair-episode").
std::string heading_slug(std::string_view heading);

}  // namespace poet
