#pragma once
// What every binary's command line shares, the build tools' included: the exit codes, --version, the hidden
// --help-json, and the parse that turns every bad command line into exit code 2. Knows nothing of the walker, so
// that poet-schema-defaults, which the simulation's build waits for, has it too (tool_flags.h adds the rest).
// Exit codes, as README.md says: 0 done, 1 runtime error, 2 bad command line, config or run directory,
// 130 interrupted.

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace poet {

// Exit code of a process given a bad command line (never CLI11's own codes 101..).
inline constexpr int kExitUsage = 2;
// Exit code of a runtime error (a diverged run, a failed write, a failure reported by workers).
inline constexpr int kExitError = 1;
// poet-coordinator's exit code when it stopped at an iteration boundary, as asked (SIGUSR1, `poetctl stop
// --at-boundary`): the run is not finished, its checkpoint is the state, and a resume goes on from there.
inline constexpr int kExitStoppedAtBoundary = 3;

// The project's version (CMake's PROJECT_VERSION), as --version and the fingerprint print it.
const char* project_version();

// The command line `app` declares, as JSON, the binary named `name`: {"name", "description", "options": [...],
// "subcommands": [...], "subcommands_required": N}, each option {"names": ["-h", "--help"] or ["id"] for a positional,
// "positional", "flag", "type" ("INT", "TEXT", ...; "" for a flag), "check" (its validators, "INT in [1 - 4096]"),
// "default" (as captured; "" when none), "required", "multiple", "env", "excludes", "needs", "description"}, and each
// subcommand the same with its own name. Hidden options and subcommands (group "") are left out.
nlohmann::ordered_json command_line_json(const CLI::App& app, const std::string& name);

// Parses argv into `app`, first adding --version (prints "<name> <version>", the name argv[0]'s file name) and the
// hidden --help-json (prints command_line_json(app) with the same name). nullopt: go on. 0: --help, --version,
// --help-json (or a flag such as --fingerprint that throws CLI::Success) printed what was asked, exit 0.
// kExitUsage (2): a bad command line, CLI11's message printed to stderr. Use: if (auto c = ...) return *c;
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv);

// A tool's exit code once its standard output is flushed: `code`, or kExitError (with a line on stderr prefixed
// `tool:`) when what it wrote did not all get there (a full disk, a failing device; not a pipe whose reader left),
// so that a truncated table or config never passes for a whole one.
// Use: int main(...) { return output_checked("poet-x", run(argc, argv)); }
int output_checked(const char* tool, int code);

}  // namespace poet
