#include "worker/handshake_failure.h"

#include <gtest/gtest.h>
#include <zmq.h>

namespace poet::worker {
namespace {

constexpr char kAt[] = "tcp://10.0.0.1:5555";

std::string said(uint16_t event, uint32_t value, bool curve) {
  return handshake_failure(event, value, curve, kAt).value_or("(nothing)");
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(HandshakeFailure, ARefusedKeyNamesTheFolder) {
  const std::string text = said(ZMQ_EVENT_HANDSHAKE_FAILED_AUTH, 400, true);
  EXPECT_TRUE(has(text, "refused this worker's CURVE key (ZAP status 400)")) << text;
  EXPECT_TRUE(has(text, "authorized/")) << text;
  EXPECT_TRUE(has(text, kAt)) << text;
}

TEST(HandshakeFailure, CurveOnOneSideOnlyIsTheCurveQuestion) {
  const std::string keyless =
      said(ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL, ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH, false);
  EXPECT_TRUE(has(keyless, "security handshake with tcp://10.0.0.1:5555 failed")) << keyless;
  EXPECT_TRUE(has(keyless, "require CURVE keys")) << keyless;
  const std::string keyed = said(ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL, ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH, true);
  EXPECT_TRUE(has(keyed, "does not use them")) << keyed;
  const std::string wrong_key = said(ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL, ZMQ_PROTOCOL_ERROR_ZMTP_CRYPTOGRAPHIC, true);
  EXPECT_TRUE(has(wrong_key, "coordinator.key")) << wrong_key;
  EXPECT_TRUE(has(said(ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL, 32, true), "coordinator.key"));
}

TEST(HandshakeFailure, APeerOfAnotherProtocolIsNotAskedAboutCurve) {
  for (const std::string& text :
       {said(ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL, ZMQ_PROTOCOL_ERROR_ZMTP_UNSPECIFIED, false),
        said(ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL, ZMQ_PROTOCOL_ERROR_ZMTP_MALFORMED_COMMAND_READY, true),
        said(ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL, ZMQ_PROTOCOL_ERROR_ZMTP_CRYPTOGRAPHIC, false),
        said(ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL, 104, false)}) {
    EXPECT_TRUE(has(text, "the peer at tcp://10.0.0.1:5555 does not speak the ZeroMQ/poet protocol")) << text;
    EXPECT_FALSE(has(text, "CURVE")) << text;
  }
}

TEST(HandshakeFailure, OtherEventsAreNoFailure) {
  for (uint16_t event : {ZMQ_EVENT_CONNECTED, ZMQ_EVENT_DISCONNECTED, ZMQ_EVENT_HANDSHAKE_SUCCEEDED})
    EXPECT_FALSE(handshake_failure(event, 0, true, kAt)) << event;
}

}  // namespace
}  // namespace poet::worker
