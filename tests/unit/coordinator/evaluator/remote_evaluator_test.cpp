// Tests coordinator/evaluator/remote_evaluator.cpp's check of the job socket's endpoint (common/zmq_endpoint.h): a
// tcp:// port outside 1..65535 (which ZeroMQ would take modulo 65536) is refused, before anything binds.

#include "coordinator/evaluator/remote_evaluator.h"

#include <gtest/gtest.h>

#include <string>

namespace poet {
namespace {

TEST(RemoteEvaluator, BindRefusesAPortOutOfRange) {
  const auto bound = RemoteEvaluator::bind("tcp://127.0.0.1:99999", DispatchSettings{}, std::stop_token{});
  ASSERT_FALSE(bound);
  EXPECT_NE(bound.error().find("1 to 65535"), std::string::npos) << bound.error();
}

}  // namespace
}  // namespace poet
