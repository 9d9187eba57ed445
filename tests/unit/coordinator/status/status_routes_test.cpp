// Tests coordinator/status/status_routes.cpp: every endpoint's status, content type and body, and the 404, 405
// and 400 rules, without a socket.

#include "coordinator/status/status_routes.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../engine/engine_test_support.h"
#include "run_directory/files/run_directory.h"
#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class StatusRoutesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(dir_ / kEventsFile) << "{\"iteration\":0,\"event\":\"pair_created\",\"pair\":0}\n"
                                      << "{\"iteration\":1,\"event\":\"solved\",\"pair\":0}\n";
    board_ = std::make_unique<StatusBoard>(dir_);
    board_->publish_run(testing::state_at(testing::tiny_config(), 3, 50.0), 3);
  }
  void TearDown() override { board_.reset(); }  // before its directory goes

  StatusResponse get(const std::string& path, const QueryParams& query = {}, const std::string& method = "GET") {
    return status_response(*board_, method, path, query);
  }

  // The JSON error body of a response, checked against its status.
  static json error_body(const StatusResponse& r) {
    EXPECT_EQ(r.content_type, kJsonType);
    const json body = json::parse(r.body);
    EXPECT_EQ(body["status"], r.status);
    EXPECT_FALSE(body["error"].get<std::string>().empty());
    return body;
  }

  poet::testing::ScratchDir scratch_;
  fs::path dir_ = scratch_.path();
  std::unique_ptr<StatusBoard> board_;
};

TEST_F(StatusRoutesTest, EveryEndpointAnswers) {
  for (const char* path : {"/status", "/pairs", "/pairs/0", "/archive", "/workers", "/events"}) {
    const StatusResponse r = get(path);
    EXPECT_EQ(r.status, 200) << path << " " << r.body;
    EXPECT_EQ(r.content_type, kJsonType) << path;
    EXPECT_TRUE(json::accept(r.body)) << path;
  }
  EXPECT_EQ(json::parse(get("/status").body)["iteration"], 3);
  EXPECT_EQ(json::parse(get("/pairs/0").body)["pair"]["id"], 0);

  const StatusResponse metrics = get("/metrics");
  EXPECT_EQ(metrics.status, 200);
  EXPECT_EQ(metrics.content_type, kMetricsType);
  EXPECT_NE(metrics.body.find("poet_iteration 3\n"), std::string::npos);

  const StatusResponse health = get("/healthz");
  EXPECT_EQ(health.status, 200);
  EXPECT_EQ(health.content_type, kJsonType);
  EXPECT_NE(health.body.find(R"("ok":true)"), std::string::npos) << health.body;
  EXPECT_NE(health.body.find(R"("state":")"), std::string::npos) << health.body;

  EXPECT_EQ(get("/status", {}, "HEAD").status, 200);  // HEAD is GET without the body (httplib drops it)
}

TEST_F(StatusRoutesTest, EventsTakeSinceAndLimit) {
  json page = json::parse(get("/events", {{"since", "1"}}).body);
  EXPECT_EQ(page["since"], "1");
  EXPECT_EQ(page["next"], "2");
  ASSERT_EQ(page["events"].size(), 1u);
  EXPECT_EQ(page["events"][0]["event"], "solved");

  page = json::parse(get("/events", {{"limit", "1"}}).body);
  EXPECT_EQ(page["events"].size(), 1u);
  EXPECT_EQ(page["more"], true);
  EXPECT_EQ(page["next"], "1");

  for (const QueryParams& bad : std::vector<QueryParams>{{{"since", "abc"}},
                                                         {{"since", "-1"}},
                                                         {{"since", ""}},
                                                         {{"since", "1.5"}},
                                                         {{"since", "99999999999999999999999"}},
                                                         {{"since", "1"}, {"since", "2"}},
                                                         {{"limit", "0"}},
                                                         {{"limit", "1001"}}}) {
    const StatusResponse r = get("/events", bad);
    EXPECT_EQ(r.status, 400) << bad.begin()->first << "=" << bad.begin()->second;
    error_body(r);
  }
  // other parameters are ignored
  EXPECT_EQ(get("/events", {{"colour", "blue"}}).status, 200);
}

TEST_F(StatusRoutesTest, UnknownPathsAre404) {
  for (const char* path : {"/nope",
                           "/status/",
                           "/pairs/",
                           "/pairs/x",
                           "/pairs/-1",
                           "/pairs/01",
                           "/pairs/1234567890",
                           "/STATUS",
                           "/events/1",
                           "/pairs/0/x",
                           "/pictures/",
                           "/pictures/nope.png",
                           "/pictures/tree",
                           "/pictures/tree.jpg",
                           "/pictures/course.svg",
                           "/pictures/pairs/0/tree.svg",
                           "/pictures/pairs/x/walk.gif",
                           "/pictures/pairs/0/walk",
                           "/pairs/x/episode",
                           "/pairs/0/episode/"}) {
    const StatusResponse r = get(path);
    EXPECT_EQ(r.status, 404) << path;
    const json body = error_body(r);
    EXPECT_NE(body["error"].get<std::string>().find("/status"), std::string::npos) << path << ": " << r.body;
  }
  // a pair that does not exist, on a path that does
  const StatusResponse r = get("/pairs/7");
  EXPECT_EQ(r.status, 404);
  EXPECT_EQ(error_body(r)["error"], "no pair 7");
  // a client's bytes that are not UTF-8 still make a JSON body
  EXPECT_EQ(get("/x\xff").status, 404);
  error_body(get("/x\xff"));
}

TEST_F(StatusRoutesTest, TheDashboardIsServedAtTheRoot) {
  const StatusResponse r = get("/");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, kHtmlType);
  EXPECT_NE(r.body.find("<html"), std::string::npos);
  for (const char* remote : {"src=\"http", "href=\"http", "url(http", "@import", "fetch(\"http", "//cdn"})
    EXPECT_EQ(r.body.find(remote), std::string::npos) << "the page loads nothing from elsewhere: " << remote;
}

TEST_F(StatusRoutesTest, PicturesAndEpisodesNeedACheckpointAndAKnownPair) {
  // the board's run directory holds no checkpoint yet: 503, saying why
  const StatusResponse early = get("/pictures/tree.svg");
  EXPECT_EQ(early.status, 503);
  EXPECT_NE(error_body(early)["error"].get<std::string>().find("checkpoint.pb"), std::string::npos) << early.body;
  EXPECT_EQ(get("/pictures/pairs/7/walk.gif").status, 404);  // no such pair
  EXPECT_EQ(get("/pairs/7/episode").status, 404);
  EXPECT_EQ(get("/pictures/pairs/0/walk.png").status, 400);  // the walk is a GIF
  EXPECT_EQ(get("/pictures/tree.gif").status, 400);
}

TEST_F(StatusRoutesTest, OtherMethodsOnKnownPathsAre405) {
  for (const char* method : {"POST", "PUT", "PATCH", "DELETE", "OPTIONS", "TRACE", "CONNECT"}) {
    const StatusResponse r = get("/status", {}, method);
    EXPECT_EQ(r.status, 405) << method;
    EXPECT_EQ(r.allow, "GET, HEAD") << method;
    error_body(r);
  }
  EXPECT_EQ(get("/pairs/0", {}, "DELETE").status, 405);
  EXPECT_EQ(get("/nope", {}, "POST").status, 404);  // an unknown path is unknown whatever the method
}

}  // namespace
}  // namespace poet
