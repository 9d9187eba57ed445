#pragma once
// "HOST:PORT" as the status socket's server binds it and its clients dial it.

#include <string>

#include "common/plumbing/expected.h"

namespace poet {

struct HostPort {
  std::string host;
  int port = 0;  // 0: an ephemeral port
};

// "HOST:PORT" or "[IPv6]:PORT", PORT in [0, 65535]; the error names the address and what is wrong with it.
Expected<HostPort> parse_host_port(const std::string& address);

}  // namespace poet
