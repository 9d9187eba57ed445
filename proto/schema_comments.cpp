#include "proto/schema_comments.h"

#include <google/protobuf/descriptor.pb.h>

#include <stdexcept>
#include <string>

#include "schema_source.h"

namespace poet {
namespace {

namespace protobuf = google::protobuf;

// A comment's lines, trimmed, joined by single spaces.
std::string one_line(const std::string& comment) {
  std::string out;
  size_t start = 0;
  while (start <= comment.size()) {
    size_t end = comment.find('\n', start);
    if (end == std::string::npos) end = comment.size();
    std::string_view line(comment.data() + start, end - start);
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t' || line.back() == '\r')) line.remove_suffix(1);
    if (!line.empty()) {
      if (!out.empty()) out += ' ';
      out += line;
    }
    start = end + 1;
  }
  return out;
}

template <class Descriptor>
std::string comment_of(const Descriptor& descriptor) {
  protobuf::SourceLocation location;
  if (!descriptor.GetSourceLocation(&location)) return "";
  const std::string leading = one_line(location.leading_comments);
  const std::string trailing = one_line(location.trailing_comments);
  if (leading.empty() || trailing.empty()) return leading + trailing;
  return leading + " " + trailing;
}

}  // namespace

const protobuf::DescriptorPool& schema_pool() {
  // the set is the build's own bytes: a set that does not parse or link is a broken build, not bad input
  static const protobuf::DescriptorPool* const pool = [] {
    protobuf::FileDescriptorSet set;
    const std::string_view bytes = schema_descriptor_set();
    if (!set.ParseFromArray(bytes.data(), static_cast<int>(bytes.size())))
      throw std::logic_error("schema_source: the embedded descriptor set does not parse");
    auto* built = new protobuf::DescriptorPool;
    for (const protobuf::FileDescriptorProto& file : set.file())
      if (!built->BuildFile(file)) throw std::logic_error("schema_source: " + file.name() + " does not build");
    return built;
  }();
  return *pool;
}

const protobuf::Descriptor* schema_message(std::string_view full_name) {
  return schema_pool().FindMessageTypeByName(std::string(full_name));
}

const protobuf::EnumDescriptor* schema_enum(std::string_view full_name) {
  return schema_pool().FindEnumTypeByName(std::string(full_name));
}

std::string schema_comment(const protobuf::Descriptor& message) { return comment_of(message); }
std::string schema_comment(const protobuf::FieldDescriptor& field) { return comment_of(field); }
std::string schema_comment(const protobuf::EnumDescriptor& enumeration) { return comment_of(enumeration); }
std::string schema_comment(const protobuf::EnumValueDescriptor& value) { return comment_of(value); }

}  // namespace poet
