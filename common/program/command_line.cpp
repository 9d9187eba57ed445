#include "common/program/command_line.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <set>
#include <vector>

namespace poet {
namespace {

// An option's names as a user types them: "-h", "--help"; a positional's own name ("id").
std::vector<std::string> option_names(const CLI::Option& option) {
  if (!option.nonpositional()) return {option.get_name(true)};
  std::vector<std::string> names;
  for (const std::string& s : option.get_snames()) names.push_back("-" + s);
  for (const std::string& l : option.get_lnames()) names.push_back("--" + l);
  return names;
}

// The other options named in an excludes() or needs(), by their longest name, sorted so the JSON is stable.
std::vector<std::string> names_of(const std::set<CLI::Option*>& options) {
  std::vector<std::string> names;
  for (const CLI::Option* option : options) names.push_back(option_names(*option).back());
  std::sort(names.begin(), names.end());
  return names;
}

nlohmann::ordered_json option_json(const CLI::Option& option) {
  const bool flag = option.get_items_expected_max() == 0;
  // get_type_name() is the type, then each validator's description after a ':' ("INT:INT in [1 - 4096]")
  const std::string full_type = flag ? "" : option.get_type_name();
  const size_t colon = full_type.find(':');
  std::string check = colon == std::string::npos ? "" : full_type.substr(colon + 1);
  for (size_t at = 0; (at = check.find(':', at)) != std::string::npos;) check.replace(at, 1, "; ");
  return {
      {"names", option_names(option)},
      {"positional", !option.nonpositional()},
      {"flag", flag},
      {"type", !option.get_option_text().empty() ? option.get_option_text() : full_type.substr(0, colon)},
      {"check", check},
      {"default", option.get_default_str()},
      {"required", option.get_required()},
      {"multiple", option.get_items_expected_max() > 1},
      {"env", option.get_envname()},
      {"excludes", names_of(option.get_excludes())},
      {"needs", names_of(option.get_needs())},
      {"description", option.get_description()},
  };
}

}  // namespace

nlohmann::ordered_json command_line_json(const CLI::App& app, const std::string& name) {
  nlohmann::ordered_json options = nlohmann::ordered_json::array();
  for (const CLI::Option* option : app.get_options()) {
    if (!option->get_group().empty()) options.push_back(option_json(*option));
  }
  nlohmann::ordered_json subcommands = nlohmann::ordered_json::array();
  // named subcommands only: option groups are nameless subcommands, and their options are the app's own
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App* s) { return !s->get_name().empty(); })) {
    if (!sub->get_group().empty()) subcommands.push_back(command_line_json(*sub, sub->get_name()));
  }
  return {{"name", name},
          {"description", app.get_description()},
          {"options", options},
          {"subcommands", subcommands},
          {"subcommands_required", app.get_require_subcommand_min()}};
}

namespace {

// --version and --help-json on the top-level app, once (a second parse of the same app adds nothing).
void add_standard_flags(CLI::App& app, const std::string& name) {
  if (app.get_option_no_throw("--version") == nullptr) {
    app.add_flag_callback(
        "--version",
        [name] {
          std::cout << name << " " << project_version() << "\n" << std::flush;
          throw CLI::Success();  // exit 0 before required options are checked, as --help
        },
        "Print the binary's name and the project's version, and exit");
  }
  if (app.get_option_no_throw("--help-json") == nullptr) {
    app.add_flag_callback(
           "--help-json",
           [&app, name] {
             std::cout << command_line_json(app, name).dump(2) << "\n" << std::flush;
             throw CLI::Success();
           },
           "Print this command line's options and subcommands as JSON (for poet-reference cli), and exit")
        ->group("");  // for tools, not people: not in --help
  }
}

}  // namespace

const char* project_version() { return POET_VERSION; }

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  const std::string name = argc > 0 ? std::filesystem::path(argv[0]).filename().string() : "";
  add_standard_flags(app, name);
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    // app.exit prints help to stdout and errors to stderr; its codes (105, 109, ...) all mean "bad command line"
    return app.exit(e) == 0 ? 0 : kExitUsage;
  }
}

int output_checked(const char* tool, int code) {
  errno = 0;
  std::cout.flush();
  const bool failed = !std::cout.good() || std::fflush(stdout) != 0 || std::ferror(stdout);
  if (!failed) return code;
  const int error = errno;
  if (error == EPIPE) return code;  // the reader stopped reading (`| head`): what it wanted, it had
  std::fprintf(stderr, "%s: cannot write standard output%s%s\n", tool, error ? ": " : "",
               error ? std::strerror(error) : "");
  return code == 0 ? kExitError : code;
}

}  // namespace poet
