// Tests common/plumbing/zmq_endpoint.cpp: a tcp:// port outside 1..65535 (which ZeroMQ would take modulo 65536) is
// refused for binding and connecting alike, * only where a socket binds, and a worker connects over tcp:// or ipc://
// only.

#include "common/plumbing/zmq_endpoint.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace poet {
namespace {

// The endpoints out of range for both uses, each problem naming its endpoint.
constexpr const char* kOutOfRange[] = {
    "tcp://127.0.0.1:99999", "tcp://127.0.0.1:65536", "tcp://127.0.0.1:0", "tcp://127.0.0.1:-1",
    "tcp://127.0.0.1:",      "tcp://127.0.0.1:55x",   "tcp://host:+80",    "tcp://host:99999999999999999999"};

// Every endpoint of kOutOfRange refused for `use`, the problem naming it: the problems.
std::vector<std::string> out_of_range_problems(EndpointUse use) {
  std::vector<std::string> problems;
  for (const char* endpoint : kOutOfRange) {
    const std::optional<std::string> problem = zmq_endpoint_problem(endpoint, use);
    EXPECT_TRUE(problem) << endpoint;
    problems.push_back(problem.value_or(""));
    EXPECT_NE(problems.back().find(endpoint), std::string::npos) << problems.back();
  }
  return problems;
}

TEST(ZmqEndpoint, ABoundPortIsOneTo65535OrFree) {
  for (const char* endpoint : {"tcp://0.0.0.0:5555", "tcp://127.0.0.1:*", "tcp://*:1", "tcp://[::1]:65535",
                               "tcp://eth0:8000", "ipc:///tmp/poet.sock", "inproc://jobs"})
    EXPECT_EQ(zmq_endpoint_problem(endpoint, EndpointUse::kBind), std::nullopt) << endpoint;
  for (const std::string& problem : out_of_range_problems(EndpointUse::kBind))
    EXPECT_NE(problem.find("1 to 65535, or * for a free one"), std::string::npos) << problem;
  EXPECT_NE(zmq_endpoint_problem("tcp://127.0.0.1", EndpointUse::kBind)->find("expected tcp://HOST:PORT"),
            std::string::npos);
}

TEST(ZmqEndpoint, AConnectedEndpointIsATcpHostAndPortOrAnIpcPath) {
  for (const char* endpoint : {"tcp://127.0.0.1:5555", "tcp://coordinator.example:1", "tcp://my_host-2:65535",
                               "tcp://[::1]:5555", "tcp://[fe80::1]:80", "ipc:///tmp/poet.sock"})
    EXPECT_EQ(zmq_endpoint_problem(endpoint, EndpointUse::kConnect), std::nullopt) << endpoint;
  for (const std::string& problem : out_of_range_problems(EndpointUse::kConnect))
    EXPECT_NE(problem.find("1 to 65535"), std::string::npos) << problem;
  EXPECT_NE(zmq_endpoint_problem("tcp://127.0.0.1:*", EndpointUse::kConnect)->find("1 to 65535"), std::string::npos);
  for (const char* endpoint : {"http://127.0.0.1:5555", "ipc://", "inproc://jobs", "tcp://*:5555", "tcp://:5555",
                               "tcp://a b:5555", "tcp://[]:5555", "tcp://[::1]x:5555", "tcp://127.0.0.1"}) {
    const std::optional<std::string> problem = zmq_endpoint_problem(endpoint, EndpointUse::kConnect);
    ASSERT_TRUE(problem) << endpoint;
    EXPECT_EQ(*problem, "expected tcp://HOST:PORT or ipc://PATH, got " + std::string(endpoint));
  }
}

// Only this machine reaches the socket: what --listen may bind without CURVE keys or --open-port.
TEST(ZmqEndpoint, LoopbackEndpointsAreThoseOnlyThisMachineReaches) {
  for (const char* endpoint : {"tcp://127.0.0.1:5555", "tcp://127.0.0.1:*", "tcp://127.1.2.3:80", "tcp://localhost:1",
                               "tcp://[::1]:5555", "ipc:///tmp/poet.sock", "inproc://jobs"})
    EXPECT_TRUE(loopback_endpoint(endpoint)) << endpoint;
  for (const char* endpoint :
       {"tcp://0.0.0.0:5555", "tcp://*:5555", "tcp://10.0.0.1:5555", "tcp://eth0:5555", "tcp://[::]:5555",
        "tcp://128.0.0.1:5555", "tcp://localhost.example.org:5555", "tcp://127.0.0.1"})
    EXPECT_FALSE(loopback_endpoint(endpoint)) << endpoint;
}

}  // namespace
}  // namespace poet
