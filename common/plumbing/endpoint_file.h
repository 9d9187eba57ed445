#pragma once
// The coordinator's endpoint file: where a running coordinator's job socket can be reached, and with CURVE its
// public key (never a secret), written into its run directory so that workers started anywhere that sees the
// directory (a shared file system: SLURM's job arrays) find it with `poet-worker --coordinator-file`. The file is
// lines of `key=value`: `endpoint=tcp://HOST:PORT`, then optionally `curve_public_key=Z85`; `#` starts a comment.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"

namespace poet {

inline constexpr char kEndpointFile[] = "coordinator.endpoint";
inline constexpr std::uintmax_t kMaxEndpointFileBytes = 4096;

struct CoordinatorEndpoint {
  std::string endpoint;          // tcp://HOST:PORT, as a worker's --connect takes it
  std::string curve_public_key;  // Z85; empty: the socket has no CURVE
};

// The endpoint that a socket bound to `bound` (tcp://HOST:PORT with its port resolved, as ZeroMQ's last endpoint
// gives it) is reached at from other machines: a wildcard host (0.0.0.0, [::], *) replaced by `host`; any other
// endpoint as it is.
std::string reachable_endpoint(std::string_view bound, std::string_view host);

// The file's text; `writer` (a process and host, say) goes in its comment line.
std::string endpoint_file_text(const CoordinatorEndpoint& endpoint, std::string_view writer);

// The text read back, every line checked: the endpoint must be one a worker can connect to, the key Z85; an
// unknown key, a repeated one or a line without `=` is an error naming its line.
Expected<CoordinatorEndpoint> parse_endpoint_file(std::string_view text);

// The file at `path` read (bounded, regular files only) and parsed; errors do not repeat the path.
Expected<CoordinatorEndpoint> read_endpoint_file(const std::filesystem::path& path);

}  // namespace poet
