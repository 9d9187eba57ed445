#pragma once
// A ZeroMQ endpoint from a command line, checked before ZeroMQ sees it: ZeroMQ reads a tcp:// port modulo 65536
// (tcp://HOST:99999 would use port 34463), so a tcp:// port must be 1 to 65535 — or *, a free one, where the
// socket binds. The coordinator's --listen binds, a worker's --connect connects.

#include <optional>
#include <string>
#include <string_view>

namespace poet {

enum class EndpointUse {
  kBind,     // tcp://HOST:PORT or tcp://HOST:*; other transports are ZeroMQ's to judge when it binds
  kConnect,  // tcp://HOST:PORT (HOST a name, an IPv4 address or a bracketed IPv6 one) or ipc://PATH, nothing else
};

// Why `endpoint` cannot be used as given, naming it, or nullopt.
std::optional<std::string> zmq_endpoint_problem(std::string_view endpoint, EndpointUse use);

// Whether only this machine can reach a socket bound to `endpoint`: tcp:// on 127.0.0.0/8, localhost or [::1], or
// a transport that is not a network's (ipc://, inproc://).
bool loopback_endpoint(std::string_view endpoint);

}  // namespace poet
