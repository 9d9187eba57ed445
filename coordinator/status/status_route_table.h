#pragma once
// The status socket's routes as data: each route's path pattern, parameters with their bounds, content type,
// answer and errors. status_routes.cpp serves from it (which paths are known, the query's bounds, the 404's list of
// endpoints) and status_reference.cpp writes docs/reference/http.md from it, so the page is what the server does.
// Constant data and a pure matcher: no board, no sockets.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "common/protocol/status_defaults.h"
#include "report/picture_request.h"

namespace poet {

inline constexpr char kJsonType[] = "application/json";
inline constexpr char kHtmlType[] = "text/html; charset=utf-8";
inline constexpr char kMetricsType[] = "text/plain; version=0.0.4; charset=utf-8";
inline constexpr char kPictureTypes[] = "image/png, image/svg+xml or image/gif, by the extension";
inline constexpr char kAllowedMethods[] = "GET, HEAD";

// What a route answers, and what get() in status_routes.cpp does for it.
enum class RouteKind {
  kDashboard,
  kStatus,
  kPairs,
  kPair,
  kEpisode,
  kArchive,
  kWorkers,
  kEvents,
  kMetrics,
  kHealth,
  kRunPicture,
  kPairPicture
};

// A placeholder of a path pattern: {id}, or {picture}.{format} in the last segment. An empty `values` is a pair id.
struct PathParam {
  std::string_view name;
  std::string_view meaning;
  std::span<const std::string_view> values;  // the values it matches; empty: a pair id (see kPairIdRule)
};

// A query parameter that is a whole number in [lo, hi], `fallback` when absent. Given twice, or out of its bounds,
// it is a 400. Other query parameters are ignored.
struct QueryParam {
  std::string_view name;
  std::string_view meaning;
  int64_t lo = 0;
  int64_t hi = 0;
  int64_t fallback = 0;
};

// An error a route itself can answer (beyond those every route can give: kEveryRouteErrors).
struct RouteError {
  int status = 0;
  std::string_view when;
};

struct StatusRoute {
  RouteKind kind = RouteKind::kStatus;
  std::string_view title = "";    // the reference page's heading for it (its anchor is the title's slug)
  std::string_view pattern = "";  // "/pairs/{id}": literal segments and placeholders
  std::string_view summary = "";  // one line: what it answers
  std::string_view content_type = "";
  std::string_view message = "";  // the answer's message of proto/status.proto, "" when the body is not one
  std::string_view body = "";     // what the body is, for a route without a message; a note on it otherwise
  std::span<const PathParam> path_params = {};
  std::span<const QueryParam> query_params = {};
  std::span<const RouteError> errors = {};
  std::string_view example_path = "";  // a request it answers (a path, maybe a query): the reference's example
};

// A pair id in a path: decimal, 0 to 999,999,999, no sign and no leading zero.
inline constexpr std::string_view kPairIdRule = "a pair's id: 0 to 999999999 in decimal, no sign, no leading zero";

// The query's `since` is bounded far beyond any events file, so that since + limit stays exact.
inline constexpr int64_t kMaxEventsSince = int64_t{1} << 50;

inline constexpr std::array<std::string_view, 5> kRunPictureNames = {"scores", "levels", "annecs", "tree", "rose"};
inline constexpr std::array<std::string_view, 4> kPairPictureNames = {"course", "filmstrip", "lineage", "walk"};
inline constexpr std::array<std::string_view, 3> kPictureFormats = {"png", "svg", "gif"};

namespace route_table {

inline constexpr PathParam kPairId[] = {{"id", "the pair", {}}};
inline constexpr PathParam kRunPicture[] = {
    {"picture", "which plot of the run (as `poet-report` draws them)", kRunPictureNames},
    {"format", "png or svg (gif is refused with a 400)", kPictureFormats}};
inline constexpr PathParam kPairPicture[] = {
    {"id", "the pair", {}},
    {"picture", "the pair's course, a filmstrip of its walk, its lineage, or its walk animated", kPairPictureNames},
    {"format", "the walk: gif; the others: png or svg (another pairing is a 400)", kPictureFormats}};
inline constexpr QueryParam kEventsQuery[] = {
    {"since", "the first line of events.jsonl to answer, counted from 0", 0, kMaxEventsSince, 0},
    {"limit", "the most events to answer", 1, kMaxEventsPerPage, kMaxEventsPerPage}};

inline constexpr RouteError kNoPair[] = {{404, "the run has no pair with this id"}};
inline constexpr RouteError kEventsErrors[] = {
    {400, "`since` or `limit` is not a whole number within its bounds, or is given twice"},
    {500, "events.jsonl exists and cannot be read"}};
inline constexpr RouteError kEpisodeErrors[] = {
    {404, "the run has no pair with this id"},
    {503, "the run directory has no checkpoint to draw from yet, or it cannot be read"}};
inline constexpr RouteError kRunPictureErrors[] = {
    {400, "the picture does not come in that format (only the walk is a GIF)"},
    {503, "the run directory has no checkpoint to draw from yet, or it cannot be read"}};
inline constexpr RouteError kPairPictureErrors[] = {
    {400, "the picture does not come in that format (the walk is a GIF, the others PNG or SVG)"},
    {404, "the run has no pair with this id"},
    {503, "the run directory has no checkpoint to draw from yet, or it cannot be read"}};

}  // namespace route_table

// Every route, in the order the reference lists them.
inline constexpr StatusRoute kStatusRoutes[] = {
    {.kind = RouteKind::kStatus,
     .title = "Status",
     .pattern = "/status",
     .summary = "The run at a glance: progress, pairs, workers, counters, ANNECS.",
     .content_type = kJsonType,
     .message = "Status",
     .example_path = "/status"},
    {.kind = RouteKind::kPairs,
     .title = "Pairs",
     .pattern = "/pairs",
     .summary = "Every pair ever created, in creation order, with its scores in brief.",
     .content_type = kJsonType,
     .message = "PairList",
     .example_path = "/pairs"},
    {.kind = RouteKind::kPair,
     .title = "Pair",
     .pattern = "/pairs/{id}",
     .summary = "One pair: its summary, its scores after each ES step, its lineage.",
     .content_type = kJsonType,
     .message = "PairDetail",
     .path_params = route_table::kPairId,
     .errors = route_table::kNoPair,
     .example_path = "/pairs/1"},
    {.kind = RouteKind::kArchive,
     .title = "Archive",
     .pattern = "/archive",
     .summary = "Every environment ever admitted.",
     .content_type = kJsonType,
     .message = "Archive",
     .example_path = "/archive"},
    {.kind = RouteKind::kWorkers,
     .title = "Workers",
     .pattern = "/workers",
     .summary = "The connected workers, the dispatcher's queue and the frames it dropped.",
     .content_type = kJsonType,
     .message = "WorkerList",
     .body = "With the local evaluator (no `--listen`) the list is empty and the counts are 0.",
     .example_path = "/workers"},
    {.kind = RouteKind::kEvents,
     .title = "Events",
     .pattern = "/events",
     .summary = "A page of the run's events (events.jsonl), from a given line.",
     .content_type = kJsonType,
     .message = "EventList",
     .body = "A line of events.jsonl that is not a JSON object is answered as {\"unparsed\": line}; before the "
             "run writes events.jsonl, a page has no events.",
     .query_params = route_table::kEventsQuery,
     .errors = route_table::kEventsErrors,
     .example_path = "/events?since=0&limit=3"},
    {.kind = RouteKind::kHealth,
     .title = "Health",
     .pattern = "/healthz",
     .summary = "The coordinator answers, and what it is doing: for probes (also on `--health-address`).",
     .content_type = kJsonType,
     .message = "Health",
     .example_path = "/healthz"},
    {.kind = RouteKind::kMetrics,
     .title = "Metrics",
     .pattern = "/metrics",
     .summary = "The run, the workers and the coordinator as Prometheus metrics.",
     .content_type = kMetricsType,
     .body = "Prometheus text format 0.0.4: every family with its HELP and TYPE lines, then its samples. The families "
             "are listed in the [metrics reference](metrics.md).",
     .example_path = "/metrics"},
    {.kind = RouteKind::kDashboard,
     .title = "Dashboard",
     .pattern = "/",
     .summary = "The dashboard: one HTML page that polls the routes above.",
     .content_type = kHtmlType,
     .body = "One HTML page with its script and style inside it; it loads nothing from elsewhere and reads only this "
             "socket's routes (relative URLs).",
     .example_path = "/"},
    {.kind = RouteKind::kEpisode,
     .title = "Pair episode",
     .pattern = "/pairs/{id}/episode",
     .summary = "The pair's current policy walked on its own course, for the dashboard's replay.",
     .content_type = kJsonType,
     .body = "A JSON object drawn from the run directory's last checkpoint: the course (ground points, obstacle boxes, "
             "the finish line), the walker's body shapes, its pose every few steps, and the episode's steps, reward "
             "and end (finished or fell). Its shape is the dashboard's, not a contract of proto/status.proto.",
     .path_params = route_table::kPairId,
     .errors = route_table::kEpisodeErrors,
     .example_path = "/pairs/1/episode"},
    {.kind = RouteKind::kRunPicture,
     .title = "Run pictures",
     .pattern = "/pictures/{picture}.{format}",
     .summary = "A plot of the run, drawn from the run directory's last checkpoint.",
     .content_type = kPictureTypes,
     .body = "The picture's bytes, as `poet-report` draws them; kept until the checkpoint changes.",
     .path_params = route_table::kRunPicture,
     .errors = route_table::kRunPictureErrors,
     .example_path = "/pictures/scores.svg"},
    {.kind = RouteKind::kPairPicture,
     .title = "Pair pictures",
     .pattern = "/pictures/pairs/{id}/{picture}.{format}",
     .summary = "A picture of one pair's episode or lineage, drawn from the run directory's last checkpoint.",
     .content_type = kPictureTypes,
     .body = "The picture's bytes; kept until the checkpoint changes.",
     .path_params = route_table::kPairPicture,
     .errors = route_table::kPairPictureErrors,
     .example_path = "/pictures/pairs/1/course.svg"},
};

// The errors any route can answer, whatever its own: a method other than GET or HEAD, and a fault in the
// coordinator (a read that threw).
inline constexpr RouteError kEveryRouteErrors[] = {
    {405, "a method other than GET or HEAD (the answer's Allow header says GET, HEAD)"},
    {500, "the coordinator failed to make the answer (the body says why)"}};

// The query parameter `name` of the route of this kind, looked up at compile time: a name the table does not give
// that route does not compile (a throw in a constant evaluation is an error).
consteval QueryParam query_param(RouteKind kind, std::string_view name) {
  for (const StatusRoute& route : kStatusRoutes)
    if (route.kind == kind)
      for (const QueryParam& param : route.query_params)
        if (param.name == name) return param;
  throw "the route table gives this route no such query parameter";
}

// A request's path matched to its route, with what its placeholders held.
struct RouteMatch {
  const StatusRoute* route = nullptr;
  int pair = -1;           // {id}, when the pattern has it
  PictureRequest picture;  // {picture}.{format}, when the pattern has them (pair set from {id})
};

// The route whose pattern the path matches, or nullopt (a 404). Exact: no trailing slash, case as written.
std::optional<RouteMatch> match_route(std::string_view path);

// The endpoints as the 404's message lists them: the patterns with {id} kept, {picture}.{format} written out as
// the pairs served, the pictures grouped by their formats ("/pictures/{scores,levels,annecs,tree,rose}.{png,svg}",
// "/pictures/pairs/{id}/walk.gif": no path that answers 400), and the query parameters ("/events?since=N&limit=N").
std::string endpoint_list();

}  // namespace poet
