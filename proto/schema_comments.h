#pragma once
// The schema's comments: what each message, field and enum value of the .proto files in the embedded descriptor
// set (schema_source.h, listed in proto/CMakeLists.txt) says it means, for pages generated from the schema, so the
// .proto file stays the one source of a field's meaning.

#include <google/protobuf/descriptor.h>

#include <string>
#include <string_view>

namespace poet {

// The descriptor set's files in a pool of their own (the generated code's pool has no comments). Built once, on
// first use; thread-safe; lives for the process.
const google::protobuf::DescriptorPool& schema_pool();

// A message or enum of schema_pool() by its full name ("poet.pb.RunConfig"); nullptr when the set has none.
const google::protobuf::Descriptor* schema_message(std::string_view full_name);
const google::protobuf::EnumDescriptor* schema_enum(std::string_view full_name);

// The comment above a declaration and the one after it on its line, each line's text trimmed and the lines
// joined by single spaces (leading first); "" when it has none. Descriptors from schema_pool() only: those of
// the generated code carry no source info.
std::string schema_comment(const google::protobuf::Descriptor& message);
std::string schema_comment(const google::protobuf::FieldDescriptor& field);
std::string schema_comment(const google::protobuf::EnumDescriptor& enumeration);
std::string schema_comment(const google::protobuf::EnumValueDescriptor& value);

}  // namespace poet
