// Tests coordinator/evaluator/remote_evaluator.cpp's check of the job socket's endpoint: a tcp:// port outside
// 1..65535 (which ZeroMQ would take modulo 65536) is refused, before anything binds.

#include "coordinator/evaluator/remote_evaluator.h"

#include <gtest/gtest.h>

#include <string>

namespace poet {
namespace {

TEST(RemoteEvaluator, ListenEndpointsNeedAPortZeroMqReadsAsWritten) {
  for (const char* endpoint : {"tcp://0.0.0.0:5555", "tcp://127.0.0.1:*", "tcp://*:1", "tcp://[::1]:65535",
                               "tcp://eth0:8000", "ipc:///tmp/poet.sock", "inproc://jobs"})
    EXPECT_EQ(listen_endpoint_problem(endpoint), std::nullopt) << endpoint;
  for (const char* endpoint : {"tcp://127.0.0.1:99999", "tcp://127.0.0.1:65536", "tcp://127.0.0.1:0",
                               "tcp://127.0.0.1:-1", "tcp://127.0.0.1:", "tcp://127.0.0.1:55x", "tcp://127.0.0.1",
                               "tcp://host:+80", "tcp://host:99999999999999999999"}) {
    const std::optional<std::string> problem = listen_endpoint_problem(endpoint);
    ASSERT_TRUE(problem) << endpoint;
    EXPECT_NE(problem->find(endpoint), std::string::npos) << *problem;
  }
  EXPECT_NE(listen_endpoint_problem("tcp://127.0.0.1:99999")->find("1 to 65535"), std::string::npos);
}

TEST(RemoteEvaluator, BindRefusesAPortOutOfRange) {
  const auto bound = RemoteEvaluator::bind("tcp://127.0.0.1:99999", DispatchSettings{}, std::stop_token{});
  ASSERT_FALSE(bound);
  EXPECT_NE(bound.error().find("1 to 65535"), std::string::npos) << bound.error();
}

}  // namespace
}  // namespace poet
