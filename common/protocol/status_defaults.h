#pragma once
// What the status socket and its clients agree on without asking: where poet-coordinator serves it unless told
// otherwise, and the largest page of events one request gets.

#include <cstdint>

namespace poet {

// Where poet-coordinator serves its status socket unless told otherwise, and where poetctl asks.
inline constexpr char kCoordinatorStatusAddress[] = "127.0.0.1:8580";

// At most this many events in one /events page; a client asks again from `next`.
inline constexpr int64_t kMaxEventsPerPage = 1000;

}  // namespace poet
