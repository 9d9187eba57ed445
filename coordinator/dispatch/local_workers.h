#pragma once
// Worker processes on this machine, started and supervised by the coordinator (--local-workers N): each is a
// plain `poet-worker --connect ENDPOINT`, as a user starts on another machine, with two additions: the local token
// in its environment, and --parent-pid, so that it ends with this process even when this one is SIGKILLed. A
// worker that dies is started again after a pause (it may have been killed by a poison job; the dispatcher's rule
// bounds that). On destruction every worker gets SIGTERM, then SIGKILL if it has not left within two seconds.

#include <sys/types.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/plumbing/expected.h"

namespace poet {

class LocalWorkers {
 public:
  // Starts `count` workers of `binary` connecting to endpoint, each with `threads` threads and `token` in its
  // environment (common/plumbing/local_token.h). extra_args go to every worker (tests pass fault switches this way).
  static Expected<std::unique_ptr<LocalWorkers>> start(const std::string& binary, const std::string& endpoint,
                                                       int count, int threads, const std::string& token,
                                                       std::vector<std::string> extra_args = {});
  ~LocalWorkers();

  // The worker binary beside this executable: <dir>/poet-worker, then <dir>/../worker/poet-worker (the build
  // tree), else "poet-worker" from PATH.
  static std::string default_binary();

  std::vector<pid_t> pids() const;

 private:
  LocalWorkers() = default;
  pid_t spawn() const;
  void supervise();

  std::string binary_;
  std::vector<std::string> args_;
  std::vector<std::string> environment_;  // this process's, and the token
  mutable std::mutex mutex_;
  std::vector<pid_t> pids_;
  std::atomic<bool> stopping_{false};
  std::thread supervisor_;
};

}  // namespace poet
