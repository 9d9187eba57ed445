// Tests tools/status_client/status_request.cpp against hostile servers on loopback (tests/support's
// ScriptedHttpServer): an answer trickled a byte at a time is cut off at the deadline for the whole answer; a body
// past the cap is refused, declared or streamed; garbage, a Content-Length that is not a number and broken chunks
// are called malformed, not slow; and a good answer comes back with its status, type and body. Small limits keep
// each case within a second or two.

#include "tools/status_client/status_request.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "loopback_port.h"
#include "scripted_http_server.h"

namespace poet {
namespace {

using namespace std::chrono_literals;
using poet::testing::HttpScript;
using poet::testing::ScriptedHttpServer;
using Clock = std::chrono::steady_clock;

constexpr StatusLimits kSmall{1s, 1 << 20};

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

Expected<StatusAnswer> ask(const ScriptedHttpServer& server, const StatusLimits& limits = kSmall) {
  return status_get(HostPort{"127.0.0.1", server.port()}, "/status", limits);
}

TEST(StatusRequest, AGoodAnswerComesBackWhole) {
  const ScriptedHttpServer server(HttpScript{{poet::testing::http_answer(R"({"iteration": 5})")}});
  const Expected<StatusAnswer> answer = ask(server);
  ASSERT_TRUE(answer) << answer.error();
  EXPECT_EQ(answer->status, 200);
  EXPECT_EQ(answer->content_type, "application/json");
  EXPECT_EQ(answer->body, R"({"iteration": 5})");
}

TEST(StatusRequest, AnAnswerTrickledAByteAtATimeIsCutOffAtTheDeadline) {
  // every read is on time (a byte each 100 ms), the whole would take some 10.6 s
  const ScriptedHttpServer server(poet::testing::trickled_answer(100ms));
  const auto started = Clock::now();
  const Expected<StatusAnswer> answer = ask(server);
  const auto took = Clock::now() - started;
  ASSERT_FALSE(answer);
  EXPECT_TRUE(contains(answer.error(), "no complete answer within 1 s")) << answer.error();
  EXPECT_LT(took, 3s);  // the deadline, and what a loaded machine adds
}

TEST(StatusRequest, ABodyPastTheCapIsRefused) {
  // declared: refused at the headers, before any of it is read
  const ScriptedHttpServer declared(poet::testing::huge_declared_answer(100));
  const auto started = Clock::now();
  const Expected<StatusAnswer> big = ask(declared);
  ASSERT_FALSE(big);
  EXPECT_TRUE(contains(big.error(), "larger than 1 MB")) << big.error();
  EXPECT_LT(Clock::now() - started, 1s);
  // streamed without a length, or in chunks: refused when it outgrows the cap
  const ScriptedHttpServer streamed(poet::testing::streamed_answer(40));
  const Expected<StatusAnswer> endless = ask(streamed);
  ASSERT_FALSE(endless);
  EXPECT_TRUE(contains(endless.error(), "larger than 1 MB")) << endless.error();
  const ScriptedHttpServer chunked(HttpScript{
      {"HTTP/1.1 200 OK\r\nTransfer-Encoding: chunked\r\n\r\n", "10000\r\n" + std::string(65536, ' ') + "\r\n"},
      0ms,
      40});
  const Expected<StatusAnswer> chunks = ask(chunked);
  ASSERT_FALSE(chunks);
  EXPECT_TRUE(contains(chunks.error(), "larger than 1 MB")) << chunks.error();
}

TEST(StatusRequest, MalformedAnswersAreCalledMalformed) {
  for (const auto& [script, message] : poet::testing::kMalformedAnswers) {
    const ScriptedHttpServer server(HttpScript{{script}});
    const auto started = Clock::now();
    const Expected<StatusAnswer> answer = ask(server);
    ASSERT_FALSE(answer) << script;
    EXPECT_TRUE(contains(answer.error(), "malformed")) << script << ": " << answer.error();
    EXPECT_TRUE(contains(answer.error(), message)) << script << ": " << answer.error();
    EXPECT_FALSE(contains(answer.error(), "within")) << script << ": " << answer.error();
    EXPECT_LT(Clock::now() - started, 1s) << script;
  }
}

TEST(StatusRequest, NothingListeningIsUnreachable) {
  const poet::testing::LoopbackPort closed(false);
  const Expected<StatusAnswer> answer = status_get(HostPort{"127.0.0.1", closed.port()}, "/status", kSmall);
  ASSERT_FALSE(answer);
  EXPECT_TRUE(contains(answer.error(), "cannot reach the coordinator")) << answer.error();
}

}  // namespace
}  // namespace poet
