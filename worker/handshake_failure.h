#pragma once
// What a failed ZeroMQ handshake with the coordinator means, in words for the worker's log: the socket monitor
// reports an event and a number, and the same event has different causes with and without CURVE keys. Pure:
// the socket loop watches the events and logs; this only names them.

#include <cstdint>
#include <optional>
#include <string>

namespace poet::worker {

// The explanation of a handshake event of the worker's socket (ZMQ_EVENT_HANDSHAKE_FAILED_AUTH, _PROTOCOL or
// _NO_DETAIL, with the event's value) with the peer at `endpoint`; nothing for any other event. `curve`: whether
// this worker uses CURVE keys. A peer that hung up during the handshake is reported as _NO_DETAIL.
std::optional<std::string> handshake_failure(uint16_t event, uint32_t value, bool curve, const std::string& endpoint);

}  // namespace poet::worker
