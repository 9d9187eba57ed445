#include "tools/reference/cli_reference.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <optional>
#include <regex>

extern char** environ;

namespace poet {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// The text of a table cell: one line, its '|' escaped, and no character Markdown would take for emphasis or HTML.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\n') {
      out += ' ';
    } else if (c == '|' || c == '*') {
      out += '\\';
      out += c;
    } else if (c == '<') {
      out += "&lt;";
    } else {
      out += c;
    }
  }
  return out;
}

std::string code_list(const Json& names) {
  std::string out;
  for (const Json& name : names) out += (out.empty() ? "`" : ", `") + name.get<std::string>() + "`";
  return out;
}

// A positional as usage writes it: LABEL_CURVE... ; an optional one in brackets.
std::string positional_usage(const Json& option) {
  std::string name = option["names"][0].get<std::string>();
  for (char& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (option["multiple"].get<bool>()) name += "...";
  return option["required"].get<bool>() ? name : "[" + name + "]";
}

std::string usage(const std::string& prefix, const Json& command) {
  std::string line = prefix + " [OPTIONS]";
  for (const Json& option : command["options"]) {
    if (option["positional"].get<bool>()) line += " " + positional_usage(option);
  }
  if (!command["subcommands"].empty())
    line += command["subcommands_required"].get<int>() > 0 ? " COMMAND" : " [COMMAND]";
  return "`" + line + "`";
}

// The default as the page shows it, or nullopt when the option has none the page can show.
std::optional<std::string> default_text(const Json& option) {
  if (option["flag"].get<bool>()) return "off";
  if (const std::string captured = option["default"].get<std::string>(); !captured.empty()) return "`" + captured + "`";
  // stated in the description where no value can be captured (the machine's core count, a file beside the binary)
  static const std::regex kStated(R"((?:\(|; )default:? ([^);]+))");
  std::smatch match;
  const std::string description = option["description"].get<std::string>();
  if (std::regex_search(description, match, kStated)) return cell(match[1].str());
  if (option["required"].get<bool>()) return "—";
  return std::nullopt;
}

// The type column: the type, and what its validators accept ("INT in [1 - 4096]", "TEXT: {nearest,first}").
std::string type_text(const Json& option) {
  if (option["flag"].get<bool>()) return "flag";
  const std::string type = option["type"].get<std::string>();
  const std::string check = option["check"].get<std::string>();
  std::string text = check.empty() ? type : check.rfind(type + " ", 0) == 0 ? check : type + ": " + check;
  if (option["multiple"].get<bool>()) text += " ...";
  return cell(text);
}

std::string meaning_text(const Json& option) {
  std::string text = option["description"].get<std::string>();
  if (!option["excludes"].empty()) text += "; not with " + code_list(option["excludes"]);
  if (!option["needs"].empty()) text += "; needs " + code_list(option["needs"]);
  if (const std::string env = option["env"].get<std::string>(); !env.empty())
    text += "; from $" + env + " when not given";
  return cell(text);
}

// The options table of a command; `where` names the command in `problems`, where each option whose default the
// page cannot show is listed ("poetctl events: --limit"). --help is shown at the top level only (every subcommand
// has it too).
std::string options_table(const Json& command, const std::string& where, bool top_level, std::string& problems) {
  std::string table = "| Option | Type | Default | Required | Meaning |\n|---|---|---|---|---|\n";
  bool any = false;
  for (const Json& option : command["options"]) {
    if (!top_level && option["names"].back() == "--help") continue;
    const std::optional<std::string> fallback = default_text(option);
    if (!fallback) problems += "\n  " + where + ": " + option["names"].back().get<std::string>();
    any = true;
    table += "| " + code_list(option["names"]) + " | " + type_text(option) + " | " + fallback.value_or("") + " | " +
             (option["required"].get<bool>() ? "yes" : "no") + " | " + meaning_text(option) + " |\n";
  }
  return any ? table : std::string("No options.\n");
}

std::string command_section(const Json& command, const std::string& path, int level, std::string& problems) {
  std::string text = std::string(level, '#') + " " + path + "\n\n" + cell(command["description"].get<std::string>()) +
                     "\n\n" + usage(path, command) + "\n\n" + options_table(command, path, level == 2, problems);
  for (const Json& sub : command["subcommands"]) {
    text += "\n" + command_section(sub, path + " " + sub["name"].get<std::string>(), 3, problems);
  }
  return text;
}

// Runs `path --help-json` and returns its standard output.
Expected<std::string> help_json_of(const fs::path& path) {
  int pipe_ends[2];
  if (pipe(pipe_ends) != 0) return Unexpected{std::string("pipe: ") + std::strerror(errno)};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_ends[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_ends[0]);
  std::string program = path.string(), flag = "--help-json";
  char* argv[] = {program.data(), flag.data(), nullptr};
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_ends[1]);
  std::string out;
  char buffer[4096];
  for (ssize_t n; spawned == 0 && (n = read(pipe_ends[0], buffer, sizeof buffer)) != 0;) {
    if (n > 0)
      out.append(buffer, static_cast<size_t>(n));
    else if (errno != EINTR)
      break;
  }
  close(pipe_ends[0]);
  if (spawned != 0) return Unexpected{program + ": " + std::strerror(spawned)};
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return Unexpected{program + " --help-json failed"};
  return out;
}

}  // namespace

const std::vector<CliBinary>& cli_binaries() {
  static const std::vector<CliBinary> kBinaries = {
      {"poet-coordinator", "coordinator"},
      {"poet-worker", "worker"},
      {"poetctl", "tools"},
      {"poet-rollout", "tools"},
      {"poet-eval", "tools"},
      {"poet-fidelity", "tools"},
      {"poet-lineage", "tools"},
      {"poet-controls", "tools"},
      {"poet-report", "tools"},
      {"poet-curves", "tools"},
      {"poet-reference", "tools"},
      {"poet-schema-defaults", "proto"},
  };
  return kBinaries;
}

Expected<std::string> cli_reference_markdown(const std::vector<Json>& command_lines) {
  std::string page =
      "# Command-line reference\n\n"
      "<!-- Generated by `poet-reference cli --binaries build` from the binaries themselves: each prints the command\n"
      "line it declares with the hidden flag --help-json. Do not edit: tests/docs/check_reference_pages.py fails when\n"
      "this page is not what poet-reference prints. -->\n\n"
      "Every binary of the project with its options and subcommands, as the binary itself declares them. This page is\n"
      "generated: after a change to a command line, remake it from the source tree with\n"
      "`build/tools/poet-reference cli --binaries build --out docs/reference/cli.md` (`--binaries` takes a build tree\n"
      "or a folder of installed binaries).\n\n"
      "Each binary answers `--help` with the options below and `--version` with its name and the project's version.\n"
      "Exit codes: 0 done, 1 runtime error, 2 bad command line, config or run directory, 130 interrupted\n"
      "(poet-coordinator: 3, stopped at an iteration boundary as asked). A default in code type is the value itself;\n"
      "one in plain text says what the binary does when the option is not given (the machine's core count, a file\n"
      "beside the binary, none).\n\n"
      "| Binary | What it is |\n|---|---|\n";
  for (const Json& command : command_lines) {
    const std::string name = command["name"].get<std::string>();
    page += "| [" + name + "](#" + name + ") | " + cell(command["description"].get<std::string>()) + " |\n";
  }
  std::string problems;
  for (const Json& command : command_lines) {
    page += "\n" + command_section(command, command["name"].get<std::string>(), 2, problems);
  }
  if (!problems.empty()) {
    return Unexpected{
        "options whose default the page cannot show (capture it with ->capture_default_str(), or "
        "state it in the description as \"(default: ...)\"):" +
        problems};
  }
  page.pop_back();  // poet-reference ends the page with its own newline, as every page
  return page;
}

Expected<std::string> cli_reference_page(const fs::path& binaries) {
  std::vector<Json> command_lines;
  for (const CliBinary& binary : cli_binaries()) {
    fs::path path = binaries / binary.place / binary.name;
    if (access(path.c_str(), X_OK) != 0) path = binaries / binary.name;
    if (access(path.c_str(), X_OK) != 0) {
      return Unexpected{binaries.string() + ": no " + binary.name + " in it nor in its " + binary.place + "/"};
    }
    const Expected<std::string> text = help_json_of(path);
    if (!text) return Unexpected{text.error()};
    Json command = Json::parse(*text, nullptr, /*allow_exceptions=*/false);
    if (command.is_discarded() || !command.is_object() || !command.contains("options")) {
      return Unexpected{path.string() + " --help-json: not the JSON of a command line"};
    }
    command["name"] = binary.name;  // as installed, whatever the file is called here
    command_lines.push_back(std::move(command));
  }
  return cli_reference_markdown(command_lines);
}

}  // namespace poet
