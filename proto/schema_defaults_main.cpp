// poet-schema-defaults OUT.h: writes schema_defaults.h, the declared default of every scalar field of the
// settings messages the simulation's types carry (EsConfig, MutationConfig, WalkerConfig), as C++ constants. The
// schema is the one home of every default; EsSettings, MutationOptions and WalkerOptions take theirs from this
// header, so they agree with a config that leaves a field out without the simulation linking protobuf. Run by
// the build.

#include <google/protobuf/descriptor.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "common/program/command_line.h"
#include "poet.pb.h"

namespace {

namespace protobuf = google::protobuf;

// EsConfig -> es_config
std::string snake_case(const std::string& name) {
  std::string out;
  for (char c : name) {
    if (c >= 'A' && c <= 'Z') {
      if (!out.empty()) out += '_';
      out += static_cast<char>(c - 'A' + 'a');
    } else {
      out += c;
    }
  }
  return out;
}

// The shortest text that reads back to the same double, which C++ reads as a literal too.
std::string double_literal(double value) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, end);
}

std::string constant(const protobuf::FieldDescriptor& f) {
  const std::string name = f.name();
  switch (f.cpp_type()) {
    case protobuf::FieldDescriptor::CPPTYPE_INT32:
      return "inline constexpr int32_t " + name + " = " + std::to_string(f.default_value_int32()) + ";";
    case protobuf::FieldDescriptor::CPPTYPE_INT64:
      return "inline constexpr int64_t " + name + " = " + std::to_string(f.default_value_int64()) + ";";
    case protobuf::FieldDescriptor::CPPTYPE_UINT64:
      return "inline constexpr uint64_t " + name + " = " + std::to_string(f.default_value_uint64()) + "u;";
    case protobuf::FieldDescriptor::CPPTYPE_DOUBLE:
      return "inline constexpr double " + name + " = " + double_literal(f.default_value_double()) + ";";
    case protobuf::FieldDescriptor::CPPTYPE_BOOL:
      return "inline constexpr bool " + name + " = " + (f.default_value_bool() ? "true" : "false") + ";";
    case protobuf::FieldDescriptor::CPPTYPE_ENUM:
      return "inline constexpr int " + name + " = " + std::to_string(f.default_value_enum()->number()) + ";  // " +
             f.default_value_enum()->name();
    default:
      return {};  // messages and strings carry no default the simulation uses
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Write schema_defaults.h: the schema's defaults of the simulation's settings as C++ constants (a build "
      "tool)"};
  std::string path;
  app.add_option("out", path, "The header to write (replaced if it exists)")->required();
  if (auto code = poet::parse_command_line(app, argc, argv)) return *code;
  std::string text =
      "#pragma once\n"
      "// Generated from proto/poet.proto by proto/schema_defaults_main.cpp: the schema's defaults of the settings\n"
      "// the simulation's types carry. Edit the schema, not this file.\n\n"
      "#include <cstdint>\n\nnamespace poet::schema_defaults {\n";
  // the messages whose settings the simulation's types carry (EsSettings, MutationOptions, WalkerOptions); the
  // engine's settings have no defaults of their own, so it needs none of the rest
  for (const protobuf::Descriptor* message : {poet::pb::EsConfig::descriptor(), poet::pb::MutationConfig::descriptor(),
                                              poet::pb::WalkerConfig::descriptor()}) {
    text += "\nnamespace " + snake_case(message->name()) + " {\n";
    for (int i = 0; i < message->field_count(); ++i) {
      const protobuf::FieldDescriptor& field = *message->field(i);
      if (field.is_repeated()) continue;
      const std::string line = constant(field);
      if (!line.empty()) text += line + "\n";
    }
    text += "}  // namespace " + snake_case(message->name()) + "\n";
  }
  text += "\n}  // namespace poet::schema_defaults\n";
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) {
    std::cerr << "poet-schema-defaults: cannot write " << path << "\n";
    return poet::kExitError;
  }
  return 0;
}
