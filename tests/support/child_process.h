#pragma once
// What the process tests share: starting a binary with its output in files, exit codes, reading files back and
// looking for text in them. The one place tests start processes.

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

extern char** environ;

namespace poet::testing {

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

// The exit status, or 128 + the signal that ended the process (as a shell reports it).
inline int exit_code(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status); }

// How a child starts, beyond its command line and output files.
struct ChildOptions {
  // Start with this signal blocked (as a parent's mask is inherited), so one sent at once is pending; 0: none.
  int blocked_signal = 0;
  // Start with no signal blocked and SIGPIPE at its default, whatever this process blocks or ignores.
  bool default_signals = false;
  std::optional<std::vector<std::string>> environment{};  // instead of this process's
  std::filesystem::path directory{};                      // the working directory; empty: this process's
};

// Starts argv[0] with stdout and stderr in the given files (created or truncated). The pid, or -1 (with errno's
// text in *error when given).
inline pid_t spawn_child(std::vector<std::string> args, const std::filesystem::path& out,
                         const std::filesystem::path& err, const ChildOptions& options = {},
                         std::string* error = nullptr) {
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> environment = options.environment.value_or(std::vector<std::string>{});
  std::vector<char*> envp;
  for (std::string& e : environment) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!options.directory.empty()) posix_spawn_file_actions_addchdir_np(&actions, options.directory.c_str());
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  short flags = 0;
  sigset_t mask;
  sigemptyset(&mask);
  if (options.blocked_signal != 0) sigaddset(&mask, options.blocked_signal);
  if (options.blocked_signal != 0 || options.default_signals) {
    posix_spawnattr_setsigmask(&attributes, &mask);
    flags |= POSIX_SPAWN_SETSIGMASK;
  }
  sigset_t defaults;
  sigemptyset(&defaults);
  if (options.default_signals) {
    sigaddset(&defaults, SIGPIPE);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    flags |= POSIX_SPAWN_SETSIGDEF;
  }
  posix_spawnattr_setflags(&attributes, flags);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(),
                             options.environment ? envp.data() : environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (rc != 0 && error != nullptr) *error = std::strerror(rc);
  return rc == 0 ? pid : -1;
}

// This process's environment without the variables named (to start a child as if they were never set).
inline std::vector<std::string> environment_without(std::initializer_list<std::string_view> names) {
  std::vector<std::string> out;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string_view entry(*e);
    bool drop = false;
    for (std::string_view name : names) drop = drop || (entry.starts_with(name) && entry.substr(name.size()).starts_with("="));
    if (!drop) out.emplace_back(entry);
  }
  return out;
}

}  // namespace poet::testing
