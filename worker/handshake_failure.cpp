#include "worker/handshake_failure.h"

#include <spdlog/fmt/fmt.h>
#include <zmq.h>

namespace poet::worker {

std::optional<std::string> handshake_failure(uint16_t event, uint32_t value, bool curve, const std::string& endpoint) {
  const std::string garbage = "the peer at " + endpoint + " does not speak the ZeroMQ/poet protocol";
  switch (event) {
    case ZMQ_EVENT_HANDSHAKE_FAILED_AUTH:
      return fmt::format(
          "the coordinator at {} refused this worker's CURVE key (ZAP status {}): its public key is not in the "
          "coordinator's authorized/ folder, or a worker holding it returned wrong results in this run (the "
          "coordinator's log says which)",
          endpoint, value);
    case ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL:
      // a ZeroMQ peer with another security mechanism: CURVE on one side only
      if (value == ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH) {
        return "the security handshake with " + endpoint + " failed: " +
               (curve ? "this worker has CURVE keys and the coordinator does not use them (no --curve-keys?)"
                      : "does the coordinator require CURVE keys (--curve-keys)?");
      }
      if (curve && (value == ZMQ_PROTOCOL_ERROR_ZMTP_CRYPTOGRAPHIC || value == ZMQ_PROTOCOL_ERROR_ZMTP_KEY_EXCHANGE))
        return "the security handshake with " + endpoint +
               " failed: is the coordinator's public key (coordinator.key) the right one?";
      return fmt::format("{} (handshake error {:#x})", garbage, value);
    case ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL:
      // the peer hung up: a CURVE server does so when the client's first box does not open with its key
      if (curve)
        return "the peer at " + endpoint +
               " hung up during the security handshake: is the coordinator's public key (coordinator.key) the right "
               "one, and is it a poet-coordinator at all?";
      // so does a CURVE coordinator whose reset overtakes its greeting: the worker cannot always tell the two apart
      return garbage + ": it hung up during the handshake (a coordinator that requires keys may do the same)";
    default:
      return std::nullopt;
  }
}

}  // namespace poet::worker
