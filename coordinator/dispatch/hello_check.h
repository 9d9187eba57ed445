#pragma once
// What a Hello says before its worker is registered: why it is refused (another protocol version, another build),
// and the worker's view as it introduced itself (its name cut to 200 bytes, its threads within 1 to 4,096).

#include <cstdint>
#include <optional>
#include <string>

#include "coordinator/dispatch/dispatch_view.h"
#include "coordinator/dispatch/drop_reason.h"
#include "wire.pb.h"

namespace poet {

struct HelloRefusal {
  DropReason reason;
  std::string why;  // told to the worker
};

// With fingerprint_digest 0, any build is accepted (for tests).
std::optional<HelloRefusal> hello_refusal(const wire::Hello& hello, uint64_t fingerprint_digest);
WorkerView view_of_hello(const WorkerId& id, const wire::Hello& hello);

}  // namespace poet
