// Tests common/plumbing/endpoint_file.cpp: the coordinator's endpoint file round-trips, a wildcard host becomes the
// advertised one, and every malformed file is refused with the line at fault named.

#include "common/plumbing/endpoint_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "scratch_dir.h"

namespace poet {
namespace {

constexpr char kKey[] = "rq:rM>}U?@Lns47E1%kR.o@n%FcmmsL/@{H8]yf7";

TEST(EndpointFile, WhatIsWrittenReadsBack) {
  const CoordinatorEndpoint endpoint{"tcp://node7:41235", kKey};
  const Expected<CoordinatorEndpoint> read = parse_endpoint_file(endpoint_file_text(endpoint, "pid 12 on node7"));
  ASSERT_TRUE(read) << read.error();
  EXPECT_EQ(read->endpoint, "tcp://node7:41235");
  EXPECT_EQ(read->curve_public_key, kKey);

  const Expected<CoordinatorEndpoint> open = parse_endpoint_file(endpoint_file_text({"tcp://10.0.0.1:5555", ""}, "x"));
  ASSERT_TRUE(open) << open.error();
  EXPECT_EQ(open->endpoint, "tcp://10.0.0.1:5555");
  EXPECT_EQ(open->curve_public_key, "");
  EXPECT_TRUE(parse_endpoint_file("\r\n# comment\r\nendpoint=tcp://h:1\r\n"));  // written on another system
}

TEST(EndpointFile, AWildcardHostBecomesTheAdvertisedOne) {
  EXPECT_EQ(reachable_endpoint("tcp://0.0.0.0:41235", "node7"), "tcp://node7:41235");
  EXPECT_EQ(reachable_endpoint("tcp://[::]:41235", "node7"), "tcp://node7:41235");
  EXPECT_EQ(reachable_endpoint("tcp://*:41235", "node7"), "tcp://node7:41235");
  EXPECT_EQ(reachable_endpoint("tcp://10.1.2.3:41235", "node7"), "tcp://10.1.2.3:41235");
  EXPECT_EQ(reachable_endpoint("tcp://127.0.0.1:9", "node7"), "tcp://127.0.0.1:9");
  EXPECT_EQ(reachable_endpoint("ipc:///tmp/x", "node7"), "ipc:///tmp/x");
}

TEST(EndpointFile, MalformedFilesAreRefusedNamingTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "no endpoint= line"},
      {"# only a comment\n", "no endpoint= line"},
      {"endpoint tcp://h:1\n", "line 1: not key=value"},
      {"endpoint=tcp://h:1\nendpoint=tcp://h:2\n", "line 2: a second endpoint"},
      {"endpoint=tcp://h:99999\n", "line 1: "},
      {"endpoint=tcp://h:*\n", "line 1: "},
      {"endpoint=udp://h:1\n", "line 1: "},
      {"endpoint=tcp://h:1\ncurve_public_key=short\n", "line 2: curve_public_key is not a Z85 key"},
      {"endpoint=tcp://h:1\ncurve_secret_key=x\n", "line 2: unknown key"},
      {"endpoint=ipc:///tmp/x\n", "line 1: the endpoint must be tcp://HOST:PORT"},
      {"endpoint=tcp://\x1b]0;x\x07h:1\n", "line 1: a control character"},
  };
  for (const auto& [text, message] : cases) {
    const Expected<CoordinatorEndpoint> read = parse_endpoint_file(text);
    ASSERT_FALSE(read) << text;
    EXPECT_NE(read.error().find(message), std::string::npos) << text << ": " << read.error();
  }
}

TEST(EndpointFile, AFileIsReadBoundedAndOnlyIfRegular) {
  testing::ScratchDir dir("endpoint_file_test");
  EXPECT_FALSE(read_endpoint_file(dir.path() / "absent"));
  EXPECT_FALSE(read_endpoint_file(dir.path()));  // a directory
  std::ofstream(dir.path() / "huge") << std::string(kMaxEndpointFileBytes + 1, '#');
  const Expected<CoordinatorEndpoint> huge = read_endpoint_file(dir.path() / "huge");
  ASSERT_FALSE(huge);
  EXPECT_NE(huge.error().find("larger than"), std::string::npos) << huge.error();
  std::ofstream(dir.path() / "good") << "endpoint=tcp://h:7\n";
  EXPECT_TRUE(read_endpoint_file(dir.path() / "good"));
}

}  // namespace
}  // namespace poet
