#pragma once
// One GET to a coordinator's status socket (HTTP/1.1, cpp-httplib) with bounded waits, and its JSON body read
// back into proto/status.proto's messages. What a client needs and nothing of the server.

#include <google/protobuf/util/json_util.h>

#include <ctime>
#include <optional>
#include <string>

#include "common/expected.h"
#include "coordinator/status_client/host_port.h"

namespace poet {

inline constexpr time_t kStatusConnectTimeoutS = 3;
inline constexpr time_t kStatusReadTimeoutS = 5;  // and for sending the request

struct StatusAnswer {
  int status = 0;
  std::string body;
};

// The answer, whatever its status; an error for people when there is none ("cannot connect (nothing listens
// there, or no answer within 3 s)").
Expected<StatusAnswer> status_get(const HostPort& where, const std::string& path);

// A body as a message; unknown fields are skipped (a newer coordinator may say more). nullopt: not that JSON.
template <class Message>
std::optional<Message> parse_status_json(const std::string& body) {
  Message message;
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = true;
  if (!google::protobuf::util::JsonStringToMessage(body, &message, options).ok()) return std::nullopt;
  return message;
}

}  // namespace poet
