#pragma once
// CURVE key files for authenticating workers (ZeroMQ's CurveZMQ): each key is its 40-character Z85 text on one
// line. A key directory holds NAME.key (public) and NAME.key_secret (secret, mode 0600) for each party
// ("coordinator", "worker"), and authorized/*.key, the public keys of the workers a coordinator accepts. Only
// files: the sockets that use the keys are the coordinator's and the worker's.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/plumbing/expected.h"

namespace poet {

// A key in Z85 text: 40 characters of the Z85 alphabet, the encoding of 32 bytes.
bool is_z85_key(std::string_view text);

// One key file: the key, then optionally a newline. Errors name the file and what is wrong with it.
Expected<std::string> read_key_file(const std::filesystem::path& path);

struct CurveKeyPair {
  std::string public_key;  // Z85
  std::string secret_key;  // Z85
};

// DIR/NAME.key and DIR/NAME.key_secret.
Expected<CurveKeyPair> read_key_pair(const std::filesystem::path& dir, std::string_view name);

// Writes DIR/NAME.key (0644) and DIR/NAME.key_secret (0600), creating DIR; refuses to replace either file, and
// writes neither when either exists. Returns an error message, or nothing.
std::optional<std::string> write_key_pair(const std::filesystem::path& dir, std::string_view name,
                                          const CurveKeyPair& keys);

// What DIR/authorized/ holds: the keys of its *.key files, and those files that hold none.
struct AuthorizedKeys {
  std::vector<std::string> keys;                 // Z85, sorted
  std::map<std::string, std::string> bad_files;  // path → what is wrong with it (read_key_file's error)
};

// DIR/authorized/*.key, a file that is not a key set aside in bad_files (one half-copied file must not lock out
// every worker); an error only when the folder is missing or cannot be listed (an empty folder is not an error:
// no worker is authorised yet).
Expected<AuthorizedKeys> scan_authorized_keys(const std::filesystem::path& dir);

}  // namespace poet
