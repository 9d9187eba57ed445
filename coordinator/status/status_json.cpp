#include "coordinator/status/status_json.h"

#include <google/protobuf/util/json_util.h>

#include "common/text/utf8.h"
#include "status.pb.h"

namespace poet {

std::string status_json(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string text;
  const auto result = google::protobuf::util::MessageToJsonString(message, &text, options);
  if (!result.ok()) {
    // only for a message the board did not make valid; still JSON, still saying what went wrong
    status::Error error;
    error.set_status(500);
    error.set_error(valid_utf8("cannot print " + message.GetTypeName() + " as JSON: " + result.ToString()));
    text.clear();
    (void)google::protobuf::util::MessageToJsonString(error, &text, options);
  }
  return text + "\n";
}

}  // namespace poet
