#pragma once
// Environment definitions in the reference's JSON form:
//   {"config": {"name", "ground_roughness", "pit_gap", "stump_width", "stump_height", "stump_float",
//               "stair_height", "stair_width", "stair_steps"}, "seed": s}
// with an absent type as [], and for a CPPN course a "cppn" key in "config" (envgen/cppn_json.h). Reading is a
// boundary: malformed JSON, missing, unknown or duplicate keys, wrong types, non-finite numbers, a seed outside [0,
// 10^6) and anything validate() refuses give an error naming the field, never an exception or a default. Every key is
// required except "name" (default: reference_name of the genes) and "cppn" (present only for a CPPN course).
// Whole-valued genes and the seed may be written as JSON integers or floats. Numbers are written so they parse back bit
// for bit.

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"
#include "simulation/envgen/env_encoding.h"

namespace poet {

// Texts and files larger than this are refused unread: a real definition is a few hundred bytes.
inline constexpr std::uintmax_t kMaxEnvDefBytes = 1u << 20;

// The "config" object alone, and back (for files that embed encodings, such as checkpoints).
nlohmann::json encoding_to_json(const EnvEncoding& encoding);
Expected<EnvEncoding> encoding_from_json(const nlohmann::json& config);

// The whole {"config", "seed"} object. to_json expects a valid definition (validate() passes, seed in range).
nlohmann::json to_json(const EnvDef& def);
Expected<EnvDef> env_def_from_json(const nlohmann::json& object);

// Text forms: env_def_json_text is pretty-printed with a trailing newline.
std::string env_def_json_text(const EnvDef& def);
Expected<EnvDef> parse_env_def(std::string_view text);

// load_env_def's errors start with the path. save_env_def refuses an invalid definition, then writes
// atomically (a temporary file in the same directory, fsync, rename over path, fsync of the directory), so a
// reader sees the old file or the new one, never a part. Returns an error message, or nothing on success.
Expected<EnvDef> load_env_def(const std::filesystem::path& path);
std::optional<std::string> save_env_def(const std::filesystem::path& path, const EnvDef& def);

}  // namespace poet
