#pragma once
// A course as Python names it: a named course ("flat", "hardcore-like", ...), an environment file, or the text
// of the file's JSON schema (the package turns a dict into it). Errors are the tools' messages.

#include <cstdint>
#include <optional>
#include <string>

#include "simulation/envgen/env_encoding.h"

namespace poet::python {

struct CourseSpec {
  EnvEncoding encoding;
  std::optional<uint32_t> seed;  // an environment file's own seed; a named course has none
};

// Throws std::invalid_argument (ValueError in Python) with the reason: an unknown name, an unreadable or
// damaged file, or JSON that is not an environment definition.
CourseSpec course_from_name_or_file(const std::string& course);
CourseSpec course_from_json_text(const std::string& text);

}  // namespace poet::python
