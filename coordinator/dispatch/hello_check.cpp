#include "coordinator/dispatch/hello_check.h"

#include <algorithm>

#include "text/text_format.h"

namespace poet {

std::optional<HelloRefusal> hello_refusal(const wire::Hello& hello, uint64_t fingerprint_digest) {
  if (hello.protocol_version() != wire::PROTOCOL_VERSION)
    return HelloRefusal{DropReason::kWrongVersion, "protocol version " + std::to_string(hello.protocol_version()) +
                                                       ", the coordinator speaks " +
                                                       std::to_string(wire::PROTOCOL_VERSION)};
  if (fingerprint_digest != 0 && hello.fingerprint_digest() != fingerprint_digest)
    return HelloRefusal{DropReason::kWrongFingerprint,
                        "build fingerprint " + hex_text(hello.fingerprint_digest()) + " differs from the coordinator's " +
                            hex_text(fingerprint_digest) +
                            ": its returns would differ (compare --fingerprint of both binaries)"};
  return std::nullopt;
}

WorkerView view_of_hello(const WorkerId& id, const wire::Hello& hello) {
  WorkerView view;
  view.id = id;
  view.name = hello.name().substr(0, 200);
  view.threads = static_cast<int>(std::clamp<uint32_t>(hello.threads(), 1, 4096));
  view.fingerprint_digest = hello.fingerprint_digest();
  return view;
}

}  // namespace poet
