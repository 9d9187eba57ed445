#pragma once
// What a Hello says before its worker is registered: why it is refused (another protocol version, a machine that
// computes differently, another build), and the facts of the worker as it introduced itself (its name cut to 200 bytes,
// its threads within 1 to 4,096).

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

// What a Hello must match: the coordinator's build and arithmetic (common/program/build_fingerprint.h). A digest of 0
// accepts any (for tests).
struct HelloExpectation {
  uint64_t fingerprint_digest = 0;
  uint64_t arithmetic_digest = 0;
  std::string arithmetic;  // the coordinator's parts, "math H, box2d H, walker H", to name those that differ
};

std::optional<HelloRefusal> hello_refusal(const wire::Hello& hello, const HelloExpectation& expected);
WorkerFacts facts_of_hello(const WorkerId& id, const wire::Hello& hello);

}  // namespace poet
