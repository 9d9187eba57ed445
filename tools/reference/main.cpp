// poet-reference: the reference pages of the documentation site (docs/reference/), generated from the code so
// they cannot drift; a subcommand per page, each printing the page to standard output or writing it to --out.
//   poet-reference config --configs deploy/configs [--out docs/reference/config.md]
//   poet-reference http --examples docs/reference/examples [--out docs/reference/http.md]
//   poet-reference metrics [--out docs/reference/metrics.md]
//   poet-reference cli --binaries build [--out docs/reference/cli.md]
// tests/docs/check_reference_pages.py regenerates every page and fails when a committed one differs.

#include <CLI/CLI.hpp>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "common/plumbing/expected.h"
#include "common/plumbing/text_file.h"
#include "common/program/tool_flags.h"
#include "tools/reference/cli_reference.h"
#include "tools/reference/config_reference.h"
#include "tools/reference/status_reference.h"

namespace {

using poet::Expected;

// One page: its subcommand (named as the page, docs/reference/<name>.md) and what makes it. `add` declares the
// subcommand's own options on it and returns the function that makes the page once they are parsed.
struct Page {
  const char* name;
  const char* about;
  std::function<std::function<Expected<std::string>()>(CLI::App&)> add;
};

std::function<Expected<std::string>()> add_config_page(CLI::App& command) {
  auto configs = std::make_shared<std::string>();
  command.add_option("--configs", *configs, "Directory of the presets (*.textproto, with paper.textproto)")->required();
  return [configs] { return poet::config_reference_page(*configs); };
}

std::function<Expected<std::string>()> add_http_page(CLI::App& command) {
  auto examples = std::make_shared<std::string>();
  command.add_option("--examples", *examples, "Directory of the example answers (docs/reference/examples)")->required();
  return [examples] { return poet::http_reference_page(*examples); };
}

std::function<Expected<std::string>()> add_metrics_page(CLI::App&) {
  return [] { return Expected<std::string>(poet::metrics_reference_page()); };
}

std::function<Expected<std::string>()> add_cli_page(CLI::App& command) {
  auto binaries = std::make_shared<std::string>();
  command
      .add_option("--binaries", *binaries,
                  "A build tree (each binary in its folder: coordinator/, worker/, tools/, proto/) or a folder of "
                  "installed binaries")
      ->required();
  return [binaries] { return poet::cli_reference_page(*binaries); };
}

const std::vector<Page>& pages() {
  static const std::vector<Page> kPages = {
      {"config", "The run config: every field with its default, the paper's value, bounds and meaning; the presets",
       add_config_page},
      {"http", "The status socket's routes: parameters, answers with every field of status.proto, errors, examples",
       add_http_page},
      {"metrics", "The metrics of /metrics: every family with its type, labels and HELP, and PromQL examples",
       add_metrics_page},
      {"cli", "Every binary's command line: each option with its type, default and meaning, and the subcommands",
       add_cli_page},
  };
  return kPages;
}

int run_tool(int argc, char** argv) {
  CLI::App app{"The reference pages of the documentation site, generated from the code"};
  app.require_subcommand(1);
  std::string out;
  app.add_option("--out", out, "Write the page to this file (atomically) instead of standard output (default: none)")
      ->option_text("FILE");
  app.fallthrough();
  poet::add_fingerprint_flag(app);
  std::vector<std::pair<CLI::App*, std::function<Expected<std::string>()>>> commands;
  for (const Page& page : pages()) {
    CLI::App* command = app.add_subcommand(page.name, page.about);
    commands.emplace_back(command, page.add(*command));
  }
  if (auto code = poet::parse_command_line(app, argc, argv)) return *code;

  for (const auto& [command, make] : commands) {
    if (!command->parsed()) continue;
    const Expected<std::string> text = make();
    if (!text) {
      std::cerr << "poet-reference: " << text.error() << "\n";
      return poet::kExitError;
    }
    if (out.empty()) {
      std::cout << *text << "\n";
    } else if (const auto error = poet::write_file_atomically(out, *text + "\n")) {
      std::cerr << "poet-reference: " << out << ": " << *error << "\n";
      return poet::kExitError;
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return poet::output_checked("poet-reference", run_tool(argc, argv)); }
