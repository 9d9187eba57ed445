#include "coordinator/daemon/endpoint_announcement.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <system_error>

#include "common/plumbing/endpoint_file.h"
#include "common/plumbing/host_name.h"
#include "common/plumbing/text_file.h"

namespace poet {

EndpointAnnouncement::EndpointAnnouncement(const std::filesystem::path& run_dir, const std::string& bound,
                                           std::string host, const std::string& curve_public_key) {
  if (host.empty()) host = host_name();
  const CoordinatorEndpoint endpoint{reachable_endpoint(bound, host), curve_public_key};
  const std::filesystem::path path = run_dir / kEndpointFile;
  const std::string writer = "poet-coordinator, pid " + std::to_string(::getpid()) + " on " + host_name();
  text_ = endpoint_file_text(endpoint, writer);
  if (auto error = write_file_atomically(path, text_)) {
    spdlog::warn("{}: {}: workers given --coordinator-file cannot find this coordinator", path.string(), *error);
    return;
  }
  path_ = path;
  spdlog::info("{} says workers reach this coordinator at {}", path.string(), endpoint.endpoint);
}

EndpointAnnouncement::~EndpointAnnouncement() {
  if (path_.empty()) return;
  // a file another coordinator of the run has written since (this one's lock released, a chain's next job already
  // up) is that one's
  const Expected<std::string> now = read_text_file(path_, kMaxEndpointFileBytes);
  if (!now || *now != text_) return;
  std::error_code error;
  std::filesystem::remove(path_, error);
  if (error) spdlog::warn("{}: {}", path_.string(), error.message());
}

}  // namespace poet
