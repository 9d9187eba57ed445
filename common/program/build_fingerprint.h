#pragma once
// What decides this build's numbers, as text: the project version, compiler, Box2D, a digest of the walker's
// constants and the arithmetic this machine computes (simulation/arithmetic_probe.h), then the float mode and
// target ISA. Processes that exchange work (coordinator and workers) must share the digest, which covers the
// lines up to the arithmetic: a worker on another ISA that computes alike shares it.

#include <cstdint>
#include <string>

namespace poet {

// Lines "key: value" (poet, compiler, box2d, walker, arithmetic, float mode, target), then "digest: <16 hex
// digits>" over the lines up to arithmetic. Each line ends with '\n'. The same text on every call.
std::string build_fingerprint();

// The digest of build_fingerprint() as a number.
uint64_t build_fingerprint_digest();

// The arithmetic probe's digest (the "arithmetic:" line's number), and its parts as "math H, box2d H, walker H".
uint64_t arithmetic_digest();
std::string arithmetic_text();

// One line for logs and benchmark context: "digest <16 hex>, arithmetic <16 hex>, float mode <flags>".
std::string build_fingerprint_line();

}  // namespace poet
