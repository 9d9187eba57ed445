#include "coordinator/status/status_routes.h"

#include <algorithm>
#include <charconv>
#include <exception>
#include <functional>
#include <optional>
#include <string_view>

#include "common/text/utf8.h"
#include "coordinator/status/dashboard.h"
#include "coordinator/status/status_json.h"

namespace poet {
namespace {

StatusResponse json(const google::protobuf::Message& message) { return {200, kJsonType, status_json(message), ""}; }

// A picture or an episode: 404 for a pair the run does not have, 503 while the run directory has no checkpoint
// to draw from (or cannot be read).
StatusResponse rendered(const StatusBoard& board, int pair, const std::function<Expected<std::string>()>& render,
                        const std::string& content_type) {
  if (pair >= 0 && !board.has_pair(pair)) return error_response(404, "no pair " + std::to_string(pair));
  Expected<std::string> bytes = render();
  if (!bytes) return error_response(503, bytes.error());
  return {200, content_type, std::move(*bytes), ""};
}

// A query parameter of the route's table (a whole number in [lo, hi] when given): the value, its fallback when
// absent, or the 400 to answer.
struct Number {
  int64_t value = 0;
  std::optional<StatusResponse> error;
};
Number query_number(const QueryParams& query, const QueryParam& param) {
  const std::string key(param.name);
  const size_t count = query.count(key);
  if (count == 0) return {param.fallback, std::nullopt};
  if (count > 1) return {0, error_response(400, key + ": given " + std::to_string(count) + " times")};
  const std::string& text = query.find(key)->second;
  int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || value < param.lo || value > param.hi)
    return {0, error_response(400, key + ": expected a whole number in [" + std::to_string(param.lo) + ", " +
                                       std::to_string(param.hi) + "], got \"" + valid_utf8(text.substr(0, 40)) + "\"")};
  return {value, std::nullopt};
}

// The events' query parameters (query_param: a name the table does not give /events does not compile).
constexpr QueryParam kEventsSince = query_param(RouteKind::kEvents, "since");
constexpr QueryParam kEventsLimit = query_param(RouteKind::kEvents, "limit");

StatusResponse get(const StatusBoard& board, const RouteMatch& match, const QueryParams& query) {
  switch (match.route->kind) {
    case RouteKind::kStatus:
      return json(board.status());
    case RouteKind::kPairs:
      return json(board.pairs());
    case RouteKind::kArchive:
      return json(board.archive());
    case RouteKind::kWorkers:
      return json(board.workers());
    case RouteKind::kMetrics:
      return {200, kMetricsType, board.metrics_text(), ""};
    case RouteKind::kHealth: {
      status::Health health;
      health.set_ok(true);
      health.set_state(board.status().state());
      return json(health);
    }
    case RouteKind::kEvents: {
      const Number since = query_number(query, kEventsSince);
      if (since.error) return *since.error;
      const Number limit = query_number(query, kEventsLimit);
      if (limit.error) return *limit.error;
      const Expected<status::EventList> events = board.events(since.value, limit.value);
      if (!events) return error_response(500, events.error());
      return json(*events);
    }
    case RouteKind::kDashboard:
      return {200, kHtmlType, std::string(dashboard_html()), ""};
    case RouteKind::kRunPicture:
    case RouteKind::kPairPicture: {
      const PictureRequest& picture = match.picture;
      if (std::optional<std::string> problem = encoding_problem(picture)) return error_response(400, *problem);
      return rendered(
          board, picture.pair, [&] { return board.pictures().picture(picture); }, mime_type(picture.encoding));
    }
    case RouteKind::kEpisode:
      return rendered(
          board, match.pair, [&] { return board.pictures().episode_json(match.pair); }, kJsonType);
    case RouteKind::kPair: {
      const std::optional<status::PairDetail> detail = board.pair(match.pair);
      if (!detail) return error_response(404, "no pair " + std::to_string(match.pair));
      return json(*detail);
    }
  }
  return error_response(500, "a route without an answer");  // unreachable: every kind is answered above
}

}  // namespace

StatusResponse error_response(int status, const std::string& message) {
  status::Error error;
  error.set_status(status);
  error.set_error(valid_utf8(message));
  StatusResponse response{status, kJsonType, status_json(error), ""};
  return response;
}

StatusResponse status_response(const StatusBoard& board, const std::string& method, const std::string& path,
                               const QueryParams& query) {
  const std::optional<RouteMatch> match = match_route(path);
  if (!match) {
    // the path is echoed only in part: it is the client's text
    return error_response(
        404, "no such endpoint: " + valid_utf8(path.substr(0, 100)) + " (endpoints: " + endpoint_list() + ")");
  }
  if (method != "GET" && method != "HEAD") {
    StatusResponse response = error_response(405, valid_utf8(method.substr(0, 20)) + " is not allowed; use GET");
    response.allow = kAllowedMethods;
    return response;
  }
  try {
    return get(board, *match, query);
  } catch (const std::exception& e) {
    return error_response(500, e.what());
  }
}

}  // namespace poet
