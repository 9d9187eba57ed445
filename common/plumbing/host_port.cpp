#include "common/plumbing/host_port.h"

#include <charconv>

#include "common/text/utf8.h"

namespace poet {

Expected<HostPort> parse_host_port(const std::string& address) {
  const std::string shown = "\"" + valid_utf8(address.substr(0, 200)) + "\"";
  if (address.size() > 300) return Unexpected{"address " + shown + "...: too long"};
  HostPort result;
  std::string port_text;
  if (address.starts_with("[")) {
    const size_t close = address.find(']');
    if (close == std::string::npos || close + 1 >= address.size() || address[close + 1] != ':')
      return Unexpected{"address " + shown + ": expected [IPv6]:PORT"};
    result.host = address.substr(1, close - 1);
    port_text = address.substr(close + 2);
  } else {
    const size_t colon = address.rfind(':');
    if (colon == std::string::npos) return Unexpected{"address " + shown + ": expected HOST:PORT"};
    result.host = address.substr(0, colon);
    port_text = address.substr(colon + 1);
    if (result.host.find(':') != std::string::npos)
      return Unexpected{"address " + shown + ": an IPv6 address goes in brackets, [::1]:PORT"};
  }
  if (result.host.empty()) return Unexpected{"address " + shown + ": no host"};
  const char* end = port_text.data() + port_text.size();
  const auto [ptr, ec] = std::from_chars(port_text.data(), end, result.port);
  if (port_text.empty() || ec != std::errc() || ptr != end || result.port < 0 || result.port > 65535)
    return Unexpected{"address " + shown + ": the port must be a number in [0, 65535]"};
  return result;
}

}  // namespace poet
