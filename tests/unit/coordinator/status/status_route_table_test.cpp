// Tests coordinator/status/status_route_table.cpp: the table is well formed (each placeholder declared, titles
// unique), its picture names are report/'s, each route's example path is matched to it, and the server answers
// each route as the table says (its content type, or one of its declared errors; 405 for another method).

#include "coordinator/status/status_route_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../../engine/engine_test_support.h"
#include "coordinator/status/status_routes.h"
#include "run_directory/files/run_directory.h"
#include "scratch_dir.h"

namespace poet {
namespace {

std::vector<std::string> placeholders(std::string_view pattern) {
  std::vector<std::string> out;
  const std::string text(pattern);
  const std::regex placeholder(R"(\{([a-z]+)\})");
  for (std::sregex_iterator it(text.begin(), text.end(), placeholder), end; it != end; ++it) out.push_back((*it)[1]);
  return out;
}

TEST(StatusRouteTableTest, EachPlaceholderIsDeclaredAndEachTitleIsUnique) {
  std::set<std::string_view> titles, patterns;
  for (const StatusRoute& route : kStatusRoutes) {
    EXPECT_TRUE(titles.insert(route.title).second) << route.title;
    EXPECT_TRUE(patterns.insert(route.pattern).second) << route.pattern;
    std::vector<std::string> declared;
    for (const PathParam& param : route.path_params) declared.emplace_back(param.name);
    EXPECT_EQ(placeholders(route.pattern), declared) << route.pattern;
    EXPECT_FALSE(route.summary.empty()) << route.pattern;
    EXPECT_FALSE(route.content_type.empty()) << route.pattern;
    EXPECT_TRUE(!route.message.empty() || !route.body.empty()) << route.pattern << ": says nothing of its answer";
    for (const QueryParam& param : route.query_params) EXPECT_LE(param.lo, param.fallback) << param.name;
    for (const QueryParam& param : route.query_params) EXPECT_LE(param.fallback, param.hi) << param.name;
  }
}

TEST(StatusRouteTableTest, ThePictureNamesAreReportsEachInTheRouteOfItsKind) {
  // picture_kind_names(): "scores, levels, ..." — every kind report/ draws
  std::istringstream names(picture_kind_names());
  std::string name;
  int kinds = 0;
  while (std::getline(names >> std::ws, name, ',')) {
    ++kinds;
    const std::optional<PictureKind> kind = picture_kind(name);
    ASSERT_TRUE(kind) << name;
    const bool run = std::count(kRunPictureNames.begin(), kRunPictureNames.end(), name) == 1;
    const bool pair = std::count(kPairPictureNames.begin(), kPairPictureNames.end(), name) == 1;
    EXPECT_NE(run, pair) << name << ": in exactly one of the picture routes";
    EXPECT_EQ(pair, needs_pair(*kind)) << name;
  }
  EXPECT_EQ(kinds, static_cast<int>(kRunPictureNames.size() + kPairPictureNames.size()));
  for (std::string_view format : kPictureFormats) EXPECT_TRUE(picture_encoding(format)) << format;
}

// An example request's path and its query ("since=0&limit=3" as parameters).
std::string example_path(const StatusRoute& route) {
  return std::string(route.example_path.substr(0, route.example_path.find('?')));
}
QueryParams example_query(const StatusRoute& route) {
  QueryParams query;
  const size_t mark = route.example_path.find('?');
  if (mark == std::string_view::npos) return query;
  std::istringstream pairs(std::string(route.example_path.substr(mark + 1)));
  for (std::string pair; std::getline(pairs, pair, '&');)
    query.emplace(pair.substr(0, pair.find('=')), pair.substr(pair.find('=') + 1));
  return query;
}

TEST(StatusRouteTableTest, EachExamplePathIsMatchedToItsRoute) {
  for (const StatusRoute& route : kStatusRoutes) {
    const std::optional<RouteMatch> match = match_route(example_path(route));
    ASSERT_TRUE(match) << route.example_path;
    EXPECT_EQ(match->route, &route) << route.example_path;
  }
  const std::optional<RouteMatch> walk = match_route("/pictures/pairs/17/walk.gif");
  ASSERT_TRUE(walk);
  EXPECT_EQ(walk->route->kind, RouteKind::kPairPicture);
  EXPECT_EQ(walk->pair, 17);
  EXPECT_EQ(walk->picture.pair, 17);
  EXPECT_EQ(walk->picture.kind, PictureKind::kWalk);
  EXPECT_EQ(walk->picture.encoding, PictureEncoding::kGif);
  EXPECT_EQ(match_route("/pairs/123456789/episode")->pair, 123456789);
  EXPECT_FALSE(match_route(""));
  EXPECT_FALSE(match_route("status"));
  EXPECT_FALSE(match_route("//status"));
}

// The server reads the events' bounds from the table at compile time; a name the table lacks would not compile.
static_assert(query_param(RouteKind::kEvents, "since").hi == kMaxEventsSince);
static_assert(query_param(RouteKind::kEvents, "limit").lo == 1);
static_assert(query_param(RouteKind::kEvents, "limit").fallback == kMaxEventsPerPage);

TEST(StatusRouteTableTest, TheEndpointListWritesOutEachRoute) {
  const std::string list = endpoint_list();
  EXPECT_NE(list.find("/pairs/{id}/episode"), std::string::npos) << list;
  EXPECT_NE(list.find("/events?since=N&limit=N"), std::string::npos) << list;
  EXPECT_NE(list.find("/pictures/{scores,levels,annecs,tree,rose}.{png,svg}, "), std::string::npos) << list;
  EXPECT_NE(list.find("/pictures/pairs/{id}/{course,filmstrip,lineage}.{png,svg}, "), std::string::npos) << list;
  EXPECT_NE(list.find("/pictures/pairs/{id}/walk.gif"), std::string::npos) << list;
  EXPECT_EQ(list.find("gif}"), std::string::npos) << list;
  // 13 endpoints, then the commas inside braces
  EXPECT_EQ(std::count(list.begin(), list.end(), ','), std::ptrdiff_t{0} + 12 + 4 + 1 + 2 + 1) << list;
}

// "/a/{b,c}.{d,e}" → the four paths it stands for, {id} as 7.
std::vector<std::string> expanded(const std::string& endpoint) {
  const size_t open = endpoint.find('{');
  if (open == std::string::npos) return {endpoint};
  const size_t close = endpoint.find('}', open);
  const std::string inside = endpoint.substr(open + 1, close - open - 1);
  std::vector<std::string> out;
  for (size_t start = 0;;) {
    const size_t comma = inside.find(',', start);
    const std::string value = inside == "id" ? "7" : inside.substr(start, comma - start);
    for (std::string& path : expanded(endpoint.substr(0, open) + value + endpoint.substr(close + 1)))
      out.push_back(std::move(path));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

// Every path the 404 lists is a route that does not answer 400 for its picture's format, and every picture and
// format served is listed.
TEST(StatusRouteTableTest, TheEndpointListHoldsExactlyThePathsServed) {
  std::set<std::string> listed;
  const std::string list = endpoint_list();
  for (size_t start = 0; start < list.size();) {
    size_t end = list.find(", /", start);
    if (end == std::string::npos) end = list.size();
    for (std::string& path : expanded(list.substr(start, end - start))) listed.insert(std::move(path));
    start = end + 2;
  }
  for (const std::string& path : listed) {
    const std::optional<RouteMatch> match = match_route(path.substr(0, path.find('?')));
    ASSERT_TRUE(match) << path;
    if (match->route->kind == RouteKind::kRunPicture || match->route->kind == RouteKind::kPairPicture) {
      EXPECT_FALSE(encoding_problem(match->picture)) << path;
    }
  }
  int pictures = 0;
  for (std::string_view format : kPictureFormats) {
    for (std::string_view name : kRunPictureNames)
      if (!encoding_problem({*picture_kind(name), *picture_encoding(format), -1})) {
        ++pictures;
        EXPECT_TRUE(listed.count("/pictures/" + std::string(name) + "." + std::string(format))) << name << format;
      }
    for (std::string_view name : kPairPictureNames)
      if (!encoding_problem({*picture_kind(name), *picture_encoding(format), 7})) {
        ++pictures;
        EXPECT_TRUE(listed.count("/pictures/pairs/7/" + std::string(name) + "." + std::string(format)))
            << name << format;
      }
  }
  EXPECT_EQ(pictures, 10 + 6 + 1);
}

// The server against the table: every route answers its example path with its declared content type, or with
// one of the errors it declares (a picture before the run directory has a checkpoint: 503).
TEST(StatusRouteTableTest, TheServerAnswersEachRouteAsDeclared) {
  poet::testing::ScratchDir scratch;
  std::ofstream(scratch.path() / kEventsFile) << "{\"iteration\":0,\"event\":\"pair_created\",\"pair\":0}\n";
  StatusBoard board(scratch.path());
  board.publish_run(testing::state_at(testing::tiny_config(), 3, 50.0), 3);
  for (const StatusRoute& route : kStatusRoutes) {
    const StatusResponse r = status_response(board, "GET", example_path(route), example_query(route));
    if (r.status == 200) {
      EXPECT_NE(route.content_type.find(r.content_type), std::string_view::npos)
          << route.pattern << " answered " << r.content_type;
    } else {
      const bool declared = std::any_of(route.errors.begin(), route.errors.end(),
                                        [&](const RouteError& e) { return e.status == r.status; });
      EXPECT_TRUE(declared) << route.pattern << " answered " << r.status << ": " << r.body;
    }
    for (const auto& [key, value] : example_query(route))
      EXPECT_TRUE(std::any_of(route.query_params.begin(), route.query_params.end(),
                              [&](const QueryParam& p) { return p.name == key; }))
          << route.example_path << ": " << key << " is not a parameter of the route";
    EXPECT_EQ(status_response(board, "POST", example_path(route), {}).status, 405) << route.pattern;
  }
  // each query parameter's bounds and fallback are the ones served
  const StatusRoute& events = *match_route("/events")->route;
  ASSERT_EQ(events.query_params.size(), 2u);
  for (const QueryParam& param : events.query_params) {
    const std::string key(param.name);
    EXPECT_EQ(status_response(board, "GET", "/events", {{key, std::to_string(param.lo)}}).status, 200) << key;
    EXPECT_EQ(status_response(board, "GET", "/events", {{key, std::to_string(param.hi)}}).status, 200) << key;
    EXPECT_EQ(status_response(board, "GET", "/events", {{key, std::to_string(param.lo - 1)}}).status, 400) << key;
    EXPECT_EQ(status_response(board, "GET", "/events", {{key, std::to_string(param.hi + 1)}}).status, 400) << key;
  }
}

}  // namespace
}  // namespace poet
