#include "coordinator/status_client/status_request.h"

#include <httplib.h>

namespace poet {
namespace {

// What went wrong with a request, for people.
std::string failure(httplib::Error error) {
  switch (error) {
    case httplib::Error::Connection:
      return "cannot connect (nothing listens there, or no answer within " + std::to_string(kStatusConnectTimeoutS) +
             " s)";
    case httplib::Error::Read:
      return "no complete answer within " + std::to_string(kStatusReadTimeoutS) + " s";
    case httplib::Error::Write:
      return "the request could not be sent";
    default:
      return "request failed (" + httplib::to_string(error) + ")";
  }
}

}  // namespace

Expected<StatusAnswer> status_get(const HostPort& where, const std::string& path) {
  httplib::Client client(where.host, where.port);
  client.set_connection_timeout(kStatusConnectTimeoutS, 0);
  client.set_read_timeout(kStatusReadTimeoutS, 0);
  client.set_write_timeout(kStatusReadTimeoutS, 0);
  const httplib::Result result = client.Get(path);
  if (!result) return Unexpected{failure(result.error())};
  return StatusAnswer{result->status, result->body};
}

}  // namespace poet
