// Tests poetctl as a real process against hostile status sockets (tests/support's ScriptedHttpServer on loopback)
// and its keygen against half a key pair: an answer trickled a byte at a time ends at the deadline for the whole
// answer, a body past the cap and malformed answers are refused with what they were, a picture command given
// something other than its picture writes nothing, the server's control characters never reach the terminal raw,
// and keygen writes neither half of a pair when either is there. Every child is bounded in time and killed, and
// the directory removed, even when a test fails.

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "child_process.h"
#include "poetctl_child.h"
#include "scratch_dir.h"
#include "scripted_http_server.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using poet::testing::contains;
using poet::testing::http_answer;
using poet::testing::HttpScript;
using poet::testing::ScriptedHttpServer;
using Outcome = poet::testing::ChildOutcome;
using Clock = std::chrono::steady_clock;

constexpr char kPng[] = "\x89PNG\r\n\x1a\n";  // a PNG's signature

class PoetctlProcessTest : public ::testing::Test {
 protected:
  Outcome poetctl(const std::vector<std::string>& args, const std::string& name) {
    return poet::testing::run_poetctl(children_, root_, args, name);
  }

  // the children go first, the directory after them
  poet::testing::ScratchDir scratch_{"poet_poetctl_process_test"};
  fs::path root_ = scratch_.path();
  poet::testing::Children children_;
};

TEST_F(PoetctlProcessTest, AnAnswerTrickledAByteAtATimeEndsAtTheDeadline) {
  // each byte comes within any read timeout; the whole answer would take some 53 s
  const ScriptedHttpServer server(poet::testing::trickled_answer(500ms));
  const auto started = Clock::now();
  const Outcome o = poetctl({"--address", server.address(), "status"}, "trickle");
  const auto took = Clock::now() - started;
  EXPECT_EQ(o.code, 1) << o.err;
  EXPECT_TRUE(contains(o.err, "no complete answer within 10 s")) << o.err;
  EXPECT_TRUE(contains(o.err, server.address())) << o.err;
  EXPECT_LT(took, 15s);
}

TEST_F(PoetctlProcessTest, ABodyPastTheCapIsRefusedAtOnce) {
  const ScriptedHttpServer server(poet::testing::huge_declared_answer(2000));
  const auto started = Clock::now();
  const Outcome o = poetctl({"--address", server.address(), "status"}, "huge");
  EXPECT_EQ(o.code, 1) << o.err;
  EXPECT_TRUE(contains(o.err, "larger than 16 MB")) << o.err;
  EXPECT_LT(Clock::now() - started, 5s);
  // streamed without a length past the cap
  const ScriptedHttpServer endless(poet::testing::streamed_answer(400));
  const Outcome streamed = poetctl({"--address", endless.address(), "pairs"}, "endless");
  EXPECT_EQ(streamed.code, 1) << streamed.err;
  EXPECT_TRUE(contains(streamed.err, "larger than 16 MB")) << streamed.err;
}

TEST_F(PoetctlProcessTest, MalformedAnswersAreCalledMalformed) {
  for (const auto& [script, said] : poet::testing::kMalformedAnswers) {
    const ScriptedHttpServer server(HttpScript{{script}});
    const auto started = Clock::now();
    const Outcome o = poetctl({"--address", server.address(), "status"}, "malformed");
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_TRUE(contains(o.err, "malformed")) << o.err;
    EXPECT_TRUE(contains(o.err, said)) << o.err;
    EXPECT_FALSE(contains(o.err, "within")) << o.err;
    EXPECT_LT(Clock::now() - started, 5s);
  }
}

TEST_F(PoetctlProcessTest, APictureCommandWritesOnlyThePictureAsked) {
  const fs::path out = root_ / "tree.png";
  // JSON for a PNG, and JSON calling itself a PNG: nothing written
  for (const std::string& answer : {http_answer("{}"), http_answer("{}", "image/png")}) {
    const ScriptedHttpServer server(HttpScript{{answer}});
    const Outcome o = poetctl({"--address", server.address(), "picture", "tree", out.string()}, "not_png");
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_TRUE(contains(o.err, "tree.png not written")) << o.err;
    EXPECT_FALSE(fs::exists(out));
  }
  const ScriptedHttpServer json(HttpScript{{http_answer("{}")}});
  const Outcome said = poetctl({"--address", json.address(), "picture", "tree", out.string()}, "said");
  EXPECT_TRUE(contains(said.err, "application/json, not image/png")) << said.err;
  // a GIF for the walk is not a PNG either, and a PNG is written as it came
  const ScriptedHttpServer gif(HttpScript{{http_answer("GIF89a...", "image/gif")}});
  EXPECT_EQ(poetctl({"--address", gif.address(), "picture", "tree", out.string()}, "gif").code, 1);
  EXPECT_FALSE(fs::exists(out));
  const std::string png = std::string(kPng) + "rest of the picture";
  const ScriptedHttpServer good(HttpScript{{http_answer(png, "image/png")}});
  const Outcome o = poetctl({"--address", good.address(), "picture", "tree", out.string()}, "png");
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_EQ(poet::testing::read_file(out), png);
  const fs::path walk = root_ / "walk.gif";
  const ScriptedHttpServer walk_gif(HttpScript{{http_answer("GIF89a-frames", "image/gif")}});
  EXPECT_EQ(poetctl({"--address", walk_gif.address(), "picture", "walk", walk.string(), "--pair", "0"}, "walk").code,
            0);
  EXPECT_EQ(poet::testing::read_file(walk), "GIF89a-frames");
}

TEST_F(PoetctlProcessTest, TheServersControlCharactersNeverReachTheTerminal) {
  // JSON escapes: the strings the client parses hold ESC, BEL, CSI (U+009B) and CR
  const std::string body =
      R"({"run_dir": "\u001b]0;pwned\u0007\u001b[2J", "mode": "poet\u009b31m", "state": "running\r"})";
  const ScriptedHttpServer status(HttpScript{{http_answer(body)}});
  const Outcome table = poetctl({"--address", status.address(), "status"}, "table");
  EXPECT_EQ(table.code, 0) << table.err;
  EXPECT_TRUE(contains(table.out, "\\u001b]0;pwned\\u0007\\u001b[2J")) << table.out;
  EXPECT_TRUE(contains(table.out, "poet\\u009b31m")) << table.out;
  for (const char raw : {'\x1b', '\x07', '\r'}) EXPECT_FALSE(contains(table.out, std::string(1, raw))) << table.out;
  EXPECT_FALSE(contains(table.out, "\xc2\x9b")) << table.out;

  // raw bytes in --json and /metrics, and in an error's text
  const ScriptedHttpServer raw(HttpScript{{http_answer("poet_iteration 5\n\x1b[31mred\x7f\n", "text/plain")}});
  const Outcome metrics = poetctl({"--address", raw.address(), "metrics"}, "metrics");
  EXPECT_EQ(metrics.code, 0) << metrics.err;
  EXPECT_EQ(metrics.out, "poet_iteration 5\n\\u001b[31mred\\u007f\n");
  const ScriptedHttpServer failing(
      HttpScript{{http_answer(R"({"status": 500, "error": "\u001b[31mred"})", "application/json", "500 Internal")}});
  const Outcome error = poetctl({"--address", failing.address(), "status"}, "error");
  EXPECT_EQ(error.code, 1);
  EXPECT_TRUE(contains(error.err, "500 \\u001b[31mred")) << error.err;
  const ScriptedHttpServer html(HttpScript{{http_answer("<p>\x1b[31mgone</p>", "text/html", "404 Not Found")}});
  const Outcome not_found = poetctl({"--address", html.address(), "status"}, "not_found");
  EXPECT_EQ(not_found.code, 1);
  EXPECT_TRUE(contains(not_found.err, "404 <p>\\u001b[31mgone</p>")) << not_found.err;
  for (const Outcome& o : {error, not_found}) EXPECT_FALSE(contains(o.err, "\x1b")) << o.err;
}

TEST_F(PoetctlProcessTest, KeygenWritesNeitherHalfOfAPairWhenEitherIsThere) {
  const fs::path keys = root_ / "keys";
  fs::create_directories(keys);
  // either half there: neither is written, and the one there is left as it was
  for (const auto& [there, other] :
       {std::pair{"worker.key", "worker.key_secret"}, {"worker.key_secret", "worker.key"}}) {
    std::ofstream(keys / there) << "an old half\n";
    const Outcome o = poetctl({"keygen", keys.string(), "worker"}, "keygen");
    EXPECT_EQ(o.code, 1) << o.err;
    EXPECT_TRUE(contains(o.err, there)) << o.err;
    EXPECT_TRUE(contains(o.err, "exists")) << o.err;
    EXPECT_FALSE(fs::exists(keys / other)) << "half a pair that does not match the other";
    EXPECT_EQ(poet::testing::read_file(keys / there), "an old half\n");
    fs::remove(keys / there);
  }
  // --authorize for the coordinator is refused before anything is written
  const Outcome authorize = poetctl({"keygen", keys.string(), "coordinator", "--authorize"}, "authorize");
  EXPECT_EQ(authorize.code, 2) << authorize.err;
  EXPECT_FALSE(fs::exists(keys / "coordinator.key_secret"));
  // a fresh pair where there is none
  EXPECT_EQ(poetctl({"keygen", keys.string(), "coordinator"}, "fresh").code, 0);
  EXPECT_TRUE(fs::exists(keys / "coordinator.key") && fs::exists(keys / "coordinator.key_secret"));
}

}  // namespace
