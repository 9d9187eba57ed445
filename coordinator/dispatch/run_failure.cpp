#include "coordinator/dispatch/run_failure.h"

namespace poet {

std::string killed_workers(const std::string& task, int deaths) {
  return task + " was running on " + std::to_string(deaths) +
         " workers when they died; the run stops rather than lose more workers to it";
}

std::string refused_by_worker(const std::string& worker, const std::string& task, bool more_tasks,
                              const std::string& error, size_t refusing) {
  return "worker " + worker + " refused " + task + (more_tasks ? " (or a later task of its job)" : "") + ": " + error +
         (refusing > 1
              ? " (and so did " + std::to_string(refusing - 1) + " other worker" + (refusing > 2 ? "s" : "") + ")"
              : "");
}

std::string refused_by_workers(const std::string& task, size_t refusing, size_t proven_connected) {
  return "workers refused " + task + " (" + std::to_string(refusing) + " of the " + std::to_string(proven_connected) +
         " proven workers connected)";
}

}  // namespace poet
