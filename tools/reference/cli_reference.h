#pragma once
// The command-line reference (docs/reference/cli.md), generated from the binaries themselves so it cannot drift:
// each binary prints the command line it declares (--help-json, common/program/command_line.h) and the page lists,
// binary by binary and subcommand by subcommand, every option with its type, default, whether it is required and
// its meaning. poet-reference prints it.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/plumbing/expected.h"

namespace poet {

// A binary of the project: its file name, and the folder of the build tree it is built in.
struct CliBinary {
  const char* name;
  const char* place;
};

// Every binary the page documents, in the page's order: the service, then the tools, then the build tool.
const std::vector<CliBinary>& cli_binaries();

// The page as Markdown for MkDocs, from each binary's --help-json (in the page's order). A binary's section names
// no path, so the page is the same whichever directory the binaries ran from. Errors: an option neither required
// nor a flag whose default is neither captured (CLI11's capture_default_str) nor stated in its description as
// "(default: ...)" or "(default ...)" — the page would leave it out.
Expected<std::string> cli_reference_markdown(const std::vector<nlohmann::json>& command_lines);

// The page, running each binary of cli_binaries() with --help-json: BINARIES/<place>/<name> (a build tree), else
// BINARIES/<name> (a folder of installed binaries). Errors: a binary not found, or that fails or prints no JSON.
Expected<std::string> cli_reference_page(const std::filesystem::path& binaries);

}  // namespace poet
