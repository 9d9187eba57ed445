#pragma once
// What the process tests share: starting a binary with its output in files, waiting for it within a time limit,
// killing whatever a test left running, exit codes, reading files back and looking for text in them. The one
// place tests start processes.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
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
  const int rc =
      posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), options.environment ? envp.data() : environ);
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
    for (std::string_view name : names)
      drop = drop || (entry.starts_with(name) && entry.substr(name.size()).starts_with("="));
    if (!drop) out.emplace_back(entry);
  }
  return out;
}

// The children of a process (a coordinator's local workers), from /proc.
inline std::vector<pid_t> children_of(pid_t pid) {
  std::vector<pid_t> out;
  std::error_code ec;
  for (const auto& task : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
    std::ifstream in(task.path() / "children");
    for (pid_t child; in >> child;) out.push_back(child);
  }
  return out;
}

// How a child that was waited for ended: its exit code (-1 when it could not be started or did not end in time)
// and what it wrote.
struct ChildOutcome {
  int code = -1;
  std::string out, err;
};

// The processes one test starts. Each writes its stdout and stderr to OUTPUT.out and OUTPUT.err; a wait is
// bounded, so that a hung child fails its test rather than hanging it; and every child still running when this
// goes is killed, with its own children, and reaped, whatever happened in the test.
class Children {
 public:
  Children() = default;
  ~Children() { kill_all(); }
  Children(const Children&) = delete;
  Children& operator=(const Children&) = delete;

  // Starts args[0] with the given arguments; its pid, or -1 (failing the test).
  pid_t start(std::vector<std::string> args, const std::filesystem::path& output, const ChildOptions& options = {}) {
    std::string error;
    const pid_t pid = spawn_child(args, stdout_of(output), stderr_of(output), options, &error);
    if (pid < 0) {
      ADD_FAILURE() << "cannot start " << args[0] << ": " << error;
      return -1;
    }
    pids_.push_back(pid);
    return pid;
  }

  // The exit code of a child that has ended (it is reaped), nothing while it runs, and -1 for a pid that is no
  // child left to reap.
  std::optional<int> ended(pid_t pid) {
    int status = 0;
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == 0) return std::nullopt;
    std::erase(pids_, pid);
    return done == pid ? exit_code(status) : -1;
  }

  // Waits at most `limit` for a child to end, calling `meanwhile` between looks (a short sleep without it); its
  // exit code, or nothing when it still runs (it stays owned and is killed at the end).
  std::optional<int> wait(pid_t pid, std::chrono::milliseconds limit, const std::function<void()>& meanwhile = {}) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    for (;;) {
      if (const std::optional<int> code = ended(pid)) return code;
      if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
      if (meanwhile) {
        meanwhile();
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    }
  }

  // Starts a child and waits at most `limit` for it to end; failing the test when it does not.
  ChildOutcome run(std::vector<std::string> args, const std::filesystem::path& output, std::chrono::milliseconds limit,
                   const ChildOptions& options = {}) {
    const std::string program = args.empty() ? std::string() : args[0];
    const pid_t pid = start(std::move(args), output, options);
    if (pid < 0) return {};
    const std::optional<int> code = wait(pid, limit);
    if (!code) {
      ADD_FAILURE() << program << " (output " << output << ") did not end within "
                    << std::chrono::duration_cast<std::chrono::seconds>(limit).count() << " s";
      return {};
    }
    return {*code, read_file(stdout_of(output)), read_file(stderr_of(output))};
  }

  // Kills every child still running, with its own children first, and reaps it.
  void kill_all() {
    for (pid_t pid : pids_) {
      for (pid_t grandchild : children_of(pid)) ::kill(grandchild, SIGKILL);
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
    pids_.clear();
  }

  static std::filesystem::path stdout_of(const std::filesystem::path& output) {
    return std::filesystem::path(output) += ".out";
  }
  static std::filesystem::path stderr_of(const std::filesystem::path& output) {
    return std::filesystem::path(output) += ".err";
  }

 private:
  std::vector<pid_t> pids_;
};

}  // namespace poet::testing
