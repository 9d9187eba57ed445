#pragma once
// The status socket's JSON bodies: proto/status.proto's messages in protobuf's JSON mapping.

#include <google/protobuf/message.h>

#include <string>

namespace poet {

// A message as one line of JSON (and '\n'): protobuf's JSON mapping with the .proto's field names, zeros printed.
std::string status_json(const google::protobuf::Message& message);

}  // namespace poet
