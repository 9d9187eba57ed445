#pragma once
// The coordinator's file descriptors: its soft RLIMIT_NOFILE is raised to the hard limit. The soft default (1024
// under systemd and most shells) is kept low for programs that wait with select(), and nothing here does
// (libmicrohttpd and ZeroMQ wait with epoll); the status listeners' caps are then fitted into it (fit_listeners).

#include <cstdint>

namespace poet {

// Raises the soft limit to the hard one (when it can) and returns the soft limit in force.
uint64_t raise_descriptor_limit();

}  // namespace poet
