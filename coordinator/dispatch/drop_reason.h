#pragma once
// Why the job socket refused or dropped a frame or a Hello: one list, counted by the dispatcher and listed by
// /metrics (poet_dropped_frames_total{reason=...}, every reason from the start, as 0 until counted).

#include <array>
#include <cstddef>

namespace poet {

enum class DropReason {
  kMalformed,          // not one WorkerMessage in one frame
  kOversized,          // a frame over the coordinator's cap
  kWrongVersion,       // a Hello of another protocol version
  kWrongFingerprint,   // a Hello of another build
  kWrongArithmetic,    // a Hello from a machine that computes differently (its arithmetic digest)
  kWorkerLimit,        // a Hello beyond the coordinator's limit of workers
  kUnknownPeer,        // a Heartbeat or Result from a peer that never said Hello
  kUnexpectedResult,   // a Result for a job the peer does not hold
  kLateResult,         // a Result for a job its backup on another worker finished first
  kBadResult,          // a Result of the wrong size or with non-finite numbers
  kUnauthorisedKey,    // CURVE: a handshake with a key not in authorized/
  kErrorFromUnproven,  // an error Result from a worker that never returned a valid one
  kWrongWorker,        // a Hello from a worker refused for wrong results
};

// The names /metrics uses, in the enum's order.
inline constexpr std::array<const char*, 13> kDropReasonNames = {
    "malformed",   "oversized",  "wrong_version", "wrong_fingerprint", "wrong_arithmetic", "worker_limit", "unknown_peer",
    "unexpected_result", "late_result", "bad_result", "unauthorised_key", "error_from_unproven", "wrong_worker"};

constexpr const char* name(DropReason reason) { return kDropReasonNames[static_cast<size_t>(reason)]; }

}  // namespace poet
