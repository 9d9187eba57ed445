#pragma once
// Policy files in the reference's (estool/POET) JSON form: `[[p0, ..., p2803], score]`, or `[[p0, ..., p2803]]`
// without a score. Reading is a boundary: any malformed, mis-shaped or non-finite input gives an error message
// naming what is wrong, never an exception or a default. Numbers are written so they parse back bit for bit.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/plumbing/expected.h"

namespace poet {

// Files larger than this are refused unread: a real policy file is about 30 KB.
inline constexpr std::uintmax_t kMaxPolicyFileBytes = 16u << 20;

struct PolicyFile {
  std::vector<double> params;   // kParamCount finite values, in Mlp's layout
  std::optional<double> score;  // finite; absent in the `[[p...]]` form
};

// load_policy's errors start with the path.
Expected<PolicyFile> parse_policy(std::string_view text);
Expected<PolicyFile> load_policy(const std::filesystem::path& path);

// The JSON text of a policy, `[[p...],score]` or `[[p...]]`, with a trailing newline. Throws
// std::invalid_argument unless params holds kParamCount finite values and the score, if any, is finite (a caller's
// bug: every policy we write comes from our own code).
std::string policy_json_text(const std::vector<double>& params, std::optional<double> score = std::nullopt);

// Refuses invalid contents (as above), then writes atomically: a temporary file in the same directory, fsync,
// rename over path, fsync of the directory, so a reader sees the old file or the new one, never a part.
// Returns an error message, or nothing on success.
std::optional<std::string> save_policy(const std::filesystem::path& path, const std::vector<double>& params,
                                       std::optional<double> score = std::nullopt);

}  // namespace poet
