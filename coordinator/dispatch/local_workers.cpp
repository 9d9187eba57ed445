#include "coordinator/dispatch/local_workers.h"

#include <signal.h>
#include <spawn.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string_view>

#include "common/plumbing/local_token.h"

extern char** environ;

namespace poet {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

int exit_code(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status); }

}  // namespace

std::string LocalWorkers::default_binary() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (const fs::path& candidate :
         {self.parent_path() / "poet-worker", self.parent_path() / ".." / "worker" / "poet-worker"})
      if (fs::exists(candidate, ec)) return fs::weakly_canonical(candidate, ec).string();
  }
  return "poet-worker";
}

Expected<std::unique_ptr<LocalWorkers>> LocalWorkers::start(const std::string& binary, const std::string& endpoint,
                                                            int count, int threads, const std::string& token,
                                                            std::vector<std::string> extra_args) {
  std::unique_ptr<LocalWorkers> workers(new LocalWorkers());
  workers->binary_ = binary;
  // --parent-pid: a worker ends with this process, also when it is killed and cannot stop its workers itself
  workers->args_ = {binary,
                    "--connect",
                    endpoint,
                    "--threads",
                    std::to_string(threads),
                    "--log-level",
                    "warn",
                    "--parent-pid",
                    std::to_string(::getpid())};
  workers->args_.insert(workers->args_.end(), extra_args.begin(), extra_args.end());
  const std::string prefix = std::string(kLocalTokenVariable) + "=";
  for (char** variable = environ; *variable != nullptr; ++variable)
    if (!std::string_view(*variable).starts_with(prefix)) workers->environment_.emplace_back(*variable);
  workers->environment_.push_back(prefix + token);
  for (int i = 0; i < count; ++i) {
    const pid_t pid = workers->spawn();
    if (pid < 0) return Unexpected{"cannot start " + binary + " (give its path with --worker-binary)"};
    workers->pids_.push_back(pid);
  }
  workers->supervisor_ = std::thread([raw = workers.get()] { raw->supervise(); });
  return workers;
}

pid_t LocalWorkers::spawn() const {
  std::vector<char*> argv;
  std::vector<std::string> args = args_;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> environment = environment_;
  std::vector<char*> envp;
  for (std::string& e : environment) envp.push_back(e.data());
  envp.push_back(nullptr);
  // the coordinator blocks SIGINT/SIGTERM for its sigwait thread; a worker must get them, so it starts with an
  // empty mask. It gets a process group of its own: a Ctrl-C in the terminal reaches the coordinator, which then
  // stops its workers, rather than every worker at once.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setpgroup(&attributes, 0);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETPGROUP);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, argv[0], nullptr, &attributes, argv.data(), envp.data());
  posix_spawnattr_destroy(&attributes);
  return rc == 0 ? pid : -1;
}

void LocalWorkers::supervise() {
  while (!stopping_) {
    std::this_thread::sleep_for(100ms);
    std::lock_guard lock(mutex_);
    for (pid_t& pid : pids_) {
      int status = 0;
      if (pid <= 0 || ::waitpid(pid, &status, WNOHANG) != pid || stopping_) continue;
      if (exit_code(status) == 0) {  // it was told to go (the run is over)
        pid = -1;
        continue;
      }
      spdlog::warn("local worker {} ended ({}); starting another", pid, exit_code(status));
      std::this_thread::sleep_for(200ms);  // a worker that dies at once must not spin
      pid = spawn();
    }
  }
}

std::vector<pid_t> LocalWorkers::pids() const {
  std::lock_guard lock(mutex_);
  return pids_;
}

LocalWorkers::~LocalWorkers() {
  stopping_ = true;
  if (supervisor_.joinable()) supervisor_.join();
  for (pid_t pid : pids_)
    if (pid > 0) ::kill(pid, SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  for (pid_t pid : pids_) {
    if (pid <= 0) continue;
    int status = 0;
    while (::waitpid(pid, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > deadline) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        break;
      }
      std::this_thread::sleep_for(10ms);
    }
  }
}

}  // namespace poet
