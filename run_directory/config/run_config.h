#pragma once
// The run configuration (pb::RunConfig of proto/poet.proto): reading it from protobuf text format, checking it,
// and handing its parts to the code that uses them. A config file names only what it changes; every other field
// keeps the schema's default (the reference implementation's value). Presets live in deploy/configs/.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"
#include "engine/run_settings.h"
#include "poet.pb.h"

namespace poet {

// Config files larger than this are refused unread: a real one is a few kilobytes.
inline constexpr std::uintmax_t kMaxRunConfigBytes = 1u << 20;

// The most iterations a run may be given, and so reach: 400× the paper's 25,200 (10 days on 256 cores) and 200× the
// reference's 50,000. A checkpoint past it is refused too: the readers keep series per iteration.
inline constexpr int kMaxIterations = 10'000'000;

// Text format in, a validated config out. Syntax errors, unknown fields, wrong types and repeated singular
// fields come back as "line L:C: <parser's message>" (1-based); a parsed config that validate() refuses comes
// back with validate()'s message. A text that sets no value at all (empty, only comments, only empty sections)
// is refused: it must say `mode:` to mean a run of every default.
Expected<pb::RunConfig> parse_run_config(std::string_view text);

// read_text_file (at most kMaxRunConfigBytes) then parse_run_config; every error starts with "<path>: ".
Expected<pb::RunConfig> load_run_config(const std::string& path);

// Checks every field (set or defaulted) against its range, the fields' agreement with each other and with the
// mode, and the size of the largest rollout batch. Every number has an upper bound taken from its meaning in the
// spec (a typo such as `l2_coeff: 1e300` or `max_children: 2000000000` is refused, not run). Returns a message
// naming the first bad field by its dotted path, with the value ("es.l2_coeff: must be in [0, 1] (got 1e+300)";
// a contradiction names both fields), or nothing when the config is runnable.
std::optional<std::string> validate(const pb::RunConfig& config);

// The config as the engine reads it, for a config that validate() accepts: every field typed, made once (the
// one route from the config into the engine).
RunSettings run_settings(const pb::RunConfig& config);

// Text format that parse_run_config reads back to an equal message (same fields set, doubles bit for bit).
// Only set fields are printed, so a default stays a default.
std::string run_config_text(const pb::RunConfig& config);

}  // namespace poet
