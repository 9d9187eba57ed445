#pragma once
// The coordinator's endpoint file (common/plumbing/endpoint_file.h) in its run directory for as long as the run
// is open here: written once the run directory is this process's (its lock taken), removed when the object goes,
// so that a worker following the file never waits on a coordinator that stopped cleanly. Errors are logged: the
// run goes on, workers given --connect still reach it.

#include <filesystem>
#include <string>

namespace poet {

class EndpointAnnouncement {
 public:
  // `bound`: the job socket's endpoint, port resolved; `host`: the name other machines reach this one by (empty:
  // this machine's host name); `curve_public_key`: empty without CURVE.
  EndpointAnnouncement(const std::filesystem::path& run_dir, const std::string& bound, std::string host,
                       const std::string& curve_public_key);
  ~EndpointAnnouncement();
  EndpointAnnouncement(const EndpointAnnouncement&) = delete;
  EndpointAnnouncement& operator=(const EndpointAnnouncement&) = delete;

 private:
  std::filesystem::path path_;  // empty when nothing was written
  std::string text_;            // what was written
};

}  // namespace poet
