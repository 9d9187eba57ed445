#pragma once
// What decides this build's numbers, as text: the project version, compiler, float mode, target ISA, Box2D
// version and a digest of the walker's constants. Processes that exchange work (coordinator and workers) must
// print the same fingerprint; the digest is the short form they are matched on.

#include <cstdint>
#include <string>

namespace poet {

// Lines "key: value" (poet, compiler, float mode, target, box2d, walker), then "digest: <16 hex digits>" over
// the lines before it. Each line ends with '\n'. The same text on every call.
std::string build_fingerprint();

// The digest of build_fingerprint() as a number.
uint64_t build_fingerprint_digest();

// One line for logs and benchmark context: "digest <16 hex digits>, float mode <flags>".
std::string build_fingerprint_line();

}  // namespace poet
