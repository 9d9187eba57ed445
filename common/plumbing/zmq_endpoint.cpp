#include "common/plumbing/zmq_endpoint.h"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace poet {
namespace {

// A host a worker can connect to: a name or IPv4 address, or an IPv6 address in brackets.
bool connectable_host(std::string_view host) {
  const auto name_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
  };
  const auto ipv6_char = [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) || c == ':' || c == '.'; };
  if (host.size() > 2 && host.front() == '[' && host.back() == ']')
    return std::ranges::all_of(host.substr(1, host.size() - 2), ipv6_char);
  return !host.empty() && std::ranges::all_of(host, name_char);
}

}  // namespace

std::optional<std::string> zmq_endpoint_problem(std::string_view endpoint, EndpointUse use) {
  constexpr std::string_view kTcp = "tcp://";
  constexpr std::string_view kIpc = "ipc://";
  const auto expected = [&] {
    return std::string(use == EndpointUse::kBind ? "expected tcp://HOST:PORT, got "
                                                 : "expected tcp://HOST:PORT or ipc://PATH, got ") +
           std::string(endpoint);
  };
  if (!endpoint.starts_with(kTcp)) {
    if (use == EndpointUse::kBind || (endpoint.starts_with(kIpc) && endpoint.size() > kIpc.size())) return std::nullopt;
    return expected();
  }
  const size_t colon = endpoint.rfind(':');
  if (colon < kTcp.size()) return expected();
  if (use == EndpointUse::kConnect && !connectable_host(endpoint.substr(kTcp.size(), colon - kTcp.size())))
    return expected();
  const std::string_view port = endpoint.substr(colon + 1);
  if (port == "*" && use == EndpointUse::kBind) return std::nullopt;
  int number = 0;
  const auto [end, error] = std::from_chars(port.data(), port.data() + port.size(), number);
  if (port.empty() || error != std::errc() || end != port.data() + port.size() || number < 1 || number > 65535)
    return "the port of " + std::string(endpoint) + " must be a number from 1 to 65535" +
           (use == EndpointUse::kBind ? ", or * for a free one" : "");
  return std::nullopt;
}

bool loopback_endpoint(std::string_view endpoint) {
  constexpr std::string_view kTcp = "tcp://";
  if (!endpoint.starts_with(kTcp)) return endpoint.starts_with("ipc://") || endpoint.starts_with("inproc://");
  const size_t colon = endpoint.rfind(':');
  if (colon < kTcp.size()) return false;
  const std::string_view host = endpoint.substr(kTcp.size(), colon - kTcp.size());
  return host.starts_with("127.") || host == "localhost" || host == "[::1]";
}

}  // namespace poet
