#include "coordinator/status/status_routes.h"

#include <algorithm>
#include <charconv>
#include <exception>
#include <functional>
#include <optional>
#include <string_view>

#include "common/utf8.h"
#include "coordinator/status/dashboard.h"
#include "coordinator/status/status_json.h"

namespace poet {
namespace {

constexpr char kEndpoints[] =
    "/, /status, /pairs, /pairs/{id}, /pairs/{id}/episode, /archive, /workers, /events?since=N, /metrics, /healthz, "
    "/pictures/{scores,levels,annecs,tree,rose}.{png,svg}, /pictures/pairs/{id}/{course,filmstrip,lineage}.{png,svg}, "
    "/pictures/pairs/{id}/walk.gif";
constexpr int64_t kMaxSince = int64_t{1} << 50;  // far beyond any events file; keeps since + limit exact

StatusResponse json(const google::protobuf::Message& message) { return {200, kJsonType, status_json(message), ""}; }

// "/pairs/17" → 17; nullopt for anything else (a sign, a leading zero, letters, more than 9 digits).
std::optional<int> pair_id(std::string_view path) {
  constexpr std::string_view kPrefix = "/pairs/";
  if (!path.starts_with(kPrefix)) return std::nullopt;
  const std::string_view digits = path.substr(kPrefix.size());
  if (digits.empty() || digits.size() > 9 || (digits.size() > 1 && digits[0] == '0')) return std::nullopt;
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) return std::nullopt;
  int id = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), id);
  if (ec != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  return id;
}

// "/pairs/17/episode" → 17.
std::optional<int> episode_pair(std::string_view path) {
  constexpr std::string_view kSuffix = "/episode";
  if (!path.ends_with(kSuffix)) return std::nullopt;
  return pair_id(path.substr(0, path.size() - kSuffix.size()));
}

// "/pictures/tree.svg" or "/pictures/pairs/3/walk.gif" → the request; nullopt for any other path. A known
// kind in an encoding it has not is still a request (the renderer names the problem).
std::optional<PictureRequest> picture_path(std::string_view path) {
  constexpr std::string_view kPrefix = "/pictures/";
  if (!path.starts_with(kPrefix)) return std::nullopt;
  std::string_view rest = path.substr(kPrefix.size());
  PictureRequest request;
  if (rest.starts_with("pairs/")) {
    const size_t slash = rest.find('/', 6);
    if (slash == std::string_view::npos) return std::nullopt;
    const std::optional<int> id = pair_id(std::string("/pairs/") + std::string(rest.substr(6, slash - 6)));
    if (!id) return std::nullopt;
    request.pair = *id;
    rest = rest.substr(slash + 1);
  }
  const size_t dot = rest.rfind('.');
  if (dot == std::string_view::npos) return std::nullopt;
  const std::optional<PictureKind> kind = picture_kind(rest.substr(0, dot));
  const std::optional<PictureEncoding> encoding = picture_encoding(rest.substr(dot + 1));
  if (!kind || !encoding || needs_pair(*kind) != (request.pair >= 0)) return std::nullopt;
  request.kind = *kind;
  request.encoding = *encoding;
  return request;
}

// A picture or an episode: 404 for a pair the run does not have, 503 while the run directory has no checkpoint
// to draw from (or cannot be read).
StatusResponse rendered(const StatusBoard& board, int pair, const std::function<Expected<std::string>()>& render,
                        const std::string& content_type) {
  if (pair >= 0 && !board.has_pair(pair)) return error_response(404, "no pair " + std::to_string(pair));
  Expected<std::string> bytes = render();
  if (!bytes) return error_response(503, bytes.error());
  return {200, content_type, std::move(*bytes), ""};
}

// A query parameter that must be a whole number in [lo, hi] when given: the value, the fallback when absent, or
// the 400 to answer.
struct Number {
  int64_t value = 0;
  std::optional<StatusResponse> error;
};
Number query_number(const QueryParams& query, const std::string& key, int64_t fallback, int64_t lo, int64_t hi) {
  const size_t count = query.count(key);
  if (count == 0) return {fallback, std::nullopt};
  if (count > 1) return {0, error_response(400, key + ": given " + std::to_string(count) + " times")};
  const std::string& text = query.find(key)->second;
  int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || value < lo || value > hi)
    return {0, error_response(400, key + ": expected a whole number in [" + std::to_string(lo) + ", " +
                                       std::to_string(hi) + "], got \"" + valid_utf8(text.substr(0, 40)) + "\"")};
  return {value, std::nullopt};
}

StatusResponse get(const StatusBoard& board, const std::string& path, const QueryParams& query) {
  if (path == "/status") return json(board.status());
  if (path == "/pairs") return json(board.pairs());
  if (path == "/archive") return json(board.archive());
  if (path == "/workers") return json(board.workers());
  if (path == "/metrics") return {200, kMetricsType, board.metrics_text(), ""};
  if (path == "/healthz") {
    status::Health health;
    health.set_ok(true);
    health.set_state(board.status().state());
    return json(health);
  }
  if (path == "/events") {
    const Number since = query_number(query, "since", 0, 0, kMaxSince);
    if (since.error) return *since.error;
    const Number limit = query_number(query, "limit", kMaxEventsPerPage, 1, kMaxEventsPerPage);
    if (limit.error) return *limit.error;
    const Expected<status::EventList> events = board.events(since.value, limit.value);
    if (!events) return error_response(500, events.error());
    return json(*events);
  }
  if (path == "/") return {200, kHtmlType, std::string(dashboard_html()), ""};
  if (const std::optional<PictureRequest> picture = picture_path(path)) {
    if (std::optional<std::string> problem = encoding_problem(*picture)) return error_response(400, *problem);
    return rendered(
        board, picture->pair, [&] { return board.pictures().picture(*picture); }, mime_type(picture->encoding));
  }
  if (const std::optional<int> episode = episode_pair(path))
    return rendered(
        board, *episode, [&] { return board.pictures().episode_json(*episode); }, kJsonType);
  const std::optional<int> id = pair_id(path);
  const std::optional<status::PairDetail> detail = board.pair(*id);  // the caller checked the path is known
  if (!detail) return error_response(404, "no pair " + std::to_string(*id));
  return json(*detail);
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
  static constexpr std::string_view kPaths[] = {"/status", "/pairs",   "/archive", "/workers",
                                                "/events", "/metrics", "/healthz"};
  bool known = path == "/" || pair_id(path) || episode_pair(path) || picture_path(path);
  for (std::string_view p : kPaths) known = known || path == p;
  if (!known) {
    // the path is echoed only in part: it is the client's text
    return error_response(404,
                          "no such endpoint: " + valid_utf8(path.substr(0, 100)) + " (endpoints: " + kEndpoints + ")");
  }
  if (method != "GET" && method != "HEAD") {
    StatusResponse response = error_response(405, valid_utf8(method.substr(0, 20)) + " is not allowed; use GET");
    response.allow = kAllowedMethods;
    return response;
  }
  try {
    return get(board, path, query);
  } catch (const std::exception& e) {
    return error_response(500, e.what());
  }
}

}  // namespace poet
