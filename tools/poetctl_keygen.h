#pragma once
// poetctl keygen: a CURVE key pair from libzmq's generator for --curve-keys, written with common/plumbing/curve_keys
// without replacing any key; no socket involved.

#include <filesystem>
#include <string>

namespace poet {

// DIR/NAME.key and DIR/NAME.key_secret; with authorize (workers only) the public key is also copied into
// DIR/authorized/. Prints what it wrote; returns the exit code.
int make_keys(const std::filesystem::path& dir, const std::string& name, bool authorize);

}  // namespace poet
