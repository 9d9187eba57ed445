#pragma once
// One GET to a coordinator's status socket (HTTP/1.1, cpp-httplib) with a deadline for the whole answer and a cap
// on its size, and its JSON body read back into proto/status.proto's messages. What a client needs and nothing of
// the server.

#include <google/protobuf/util/json_util.h>

#include <chrono>
#include <cstddef>
#include <ctime>
#include <optional>
#include <string>

#include "common/plumbing/expected.h"
#include "common/plumbing/host_port.h"

namespace poet {

inline constexpr time_t kStatusConnectTimeoutS = 3;

// What one request may take. The deadline is for the whole answer, from the connection to its last byte: a
// server that sends a byte now and then (each read on time) is cut off as surely as one that sends nothing.
struct StatusLimits {
  std::chrono::milliseconds deadline;
  size_t max_body_bytes;
};

// The JSON and text endpoints: a status is a kilobyte, a page of 1000 events or a long run's pair list a few
// hundred; 16 MB leaves room for runs far longer than any yet, and bounds what a hostile server can make us hold.
inline constexpr StatusLimits kStatusTextLimits{std::chrono::seconds(10), size_t{16} << 20};
// The pictures: the walk's GIF is the largest, about 2 KB per frame (a frame every 4 steps), 1 MB for a
// 2000-step episode; 256 MB holds the walk of half a million steps. A longer one is drawn from the run's files
// (poetctl picture --run-dir) rather than held in memory here. Drawing one may take the server a while.
inline constexpr StatusLimits kStatusPictureLimits{std::chrono::seconds(60), size_t{256} << 20};

struct StatusAnswer {
  int status = 0;
  std::string content_type;  // as the server sent it ("image/png", "application/json"); empty when it sent none
  std::string body;
};

// The answer, whatever its status; else an error for people that says which of these it was: nothing to connect
// to, no whole answer within the deadline, a body larger than the cap, an answer that is not well-formed HTTP (a
// status line, headers, Content-Length or chunks that cannot be read, or a connection closed before the end).
Expected<StatusAnswer> status_get(const HostPort& where, const std::string& path,
                                  const StatusLimits& limits = kStatusTextLimits);

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
