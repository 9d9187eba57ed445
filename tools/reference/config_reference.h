#pragma once
// The config reference (docs/reference/config.md), generated from the code so it cannot drift: every field of
// the run config (pb::RunConfig and its parts, down to the environment targets) with its dotted path, type,
// default (the schema's, the reference implementation's value), the paper preset's value, the rules validate()
// applies (config_rules.h) and its meaning (its comment in proto/poet.proto, read from the embedded descriptor set,
// proto/schema_comments.h); then the fields each preset of deploy/configs changes. poet-reference prints it.

#include <filesystem>
#include <string>

#include "common/plumbing/expected.h"

namespace poet {

// The page as Markdown for MkDocs. `configs_dir` holds the presets (*.textproto, read as run configs; it must
// hold paper.textproto, the paper column's source). The page names presets by file name only, so it is the same
// whichever path reaches the directory. Errors: a preset that does not load (its message), no paper.textproto,
// a config field or enum value without a comment in the schema (the page would leave its meaning out).
Expected<std::string> config_reference_page(const std::filesystem::path& configs_dir);

}  // namespace poet
