#include "common/plumbing/endpoint_file.h"

#include "common/plumbing/curve_keys.h"
#include "common/plumbing/text_file.h"
#include "common/plumbing/zmq_endpoint.h"

namespace poet {

std::string reachable_endpoint(std::string_view bound, std::string_view host) {
  constexpr std::string_view kTcp = "tcp://";
  const size_t colon = bound.rfind(':');
  if (bound.substr(0, kTcp.size()) != kTcp || colon == std::string_view::npos || colon < kTcp.size())
    return std::string(bound);
  const std::string_view bound_host = bound.substr(kTcp.size(), colon - kTcp.size());
  if (bound_host != "0.0.0.0" && bound_host != "[::]" && bound_host != "*") return std::string(bound);
  return std::string(kTcp) + std::string(host) + std::string(bound.substr(colon));
}

std::string endpoint_file_text(const CoordinatorEndpoint& endpoint, std::string_view writer) {
  std::string text = "# the job socket of the coordinator of this run (" + std::string(writer) + ")\n";
  text += "endpoint=" + endpoint.endpoint + "\n";
  if (!endpoint.curve_public_key.empty()) text += "curve_public_key=" + endpoint.curve_public_key + "\n";
  return text;
}

Expected<CoordinatorEndpoint> parse_endpoint_file(std::string_view text) {
  CoordinatorEndpoint parsed;
  bool has_key = false;
  int number = 0;
  while (!text.empty()) {
    const size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
    ++number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    const std::string where = "line " + std::to_string(number) + ": ";
    for (const char c : line)  // nothing that could drive a terminal reaches a log line
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return Unexpected{where + "a control character"};
    const size_t equals = line.find('=');
    if (equals == std::string_view::npos) return Unexpected{where + "not key=value"};
    const std::string_view key = line.substr(0, equals);
    const std::string_view value = line.substr(equals + 1);
    if (key == "endpoint") {
      if (!parsed.endpoint.empty()) return Unexpected{where + "a second endpoint"};
      if (value.substr(0, 6) != "tcp://") return Unexpected{where + "the endpoint must be tcp://HOST:PORT"};
      if (auto problem = zmq_endpoint_problem(value, EndpointUse::kConnect)) return Unexpected{where + *problem};
      parsed.endpoint = value;
    } else if (key == "curve_public_key") {
      if (has_key) return Unexpected{where + "a second curve_public_key"};
      if (!is_z85_key(value)) return Unexpected{where + "curve_public_key is not a Z85 key of 40 characters"};
      parsed.curve_public_key = value;
      has_key = true;
    } else {
      return Unexpected{where + "unknown key (endpoint and curve_public_key are known)"};
    }
  }
  if (parsed.endpoint.empty()) return Unexpected{std::string("no endpoint= line")};
  return parsed;
}

Expected<CoordinatorEndpoint> read_endpoint_file(const std::filesystem::path& path) {
  Expected<std::string> text = read_text_file(path, kMaxEndpointFileBytes);
  if (!text) return Unexpected{text.error()};
  return parse_endpoint_file(*text);
}

}  // namespace poet
