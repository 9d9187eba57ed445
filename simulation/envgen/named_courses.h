#pragma once
// Encodings with names, used across the project (evaluation, benchmarks, tests, the CLI's --env):
// "flat", "r1", "r3", "hard" and "hardcore-like". Each encoding's name is its course name.

#include <optional>
#include <span>
#include <string_view>

#include "simulation/envgen/env_encoding.h"

namespace poet {

// The encoding of a named course, or nothing for an unknown name. Every named course passes validate().
std::optional<EnvEncoding> named_course(std::string_view name);

// The known names, in a fixed order.
std::span<const std::string_view> course_names();

}  // namespace poet
