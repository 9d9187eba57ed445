#pragma once
// The wire protocol's timings (proto/wire.proto) in one place that both sides include, as zguide's mdp.h is for
// Majordomo. The coordinator tells its own in Welcome; these are its defaults, and what a worker assumes of a
// Welcome that leaves them out.

#include <algorithm>

namespace poet::wire_timing {

inline constexpr int kLivenessMs = 5000;  // a peer silent this long is dead
inline constexpr int kHeartbeatsPerLiveness = 5;

// Send something at least this often: a few heartbeats fit in the liveness window, so one lost is no death.
constexpr int heartbeat_ms(int liveness_ms) { return std::max(liveness_ms / kHeartbeatsPerLiveness, 1); }

inline constexpr int kHeartbeatMs = heartbeat_ms(kLivenessMs);

}  // namespace poet::wire_timing
