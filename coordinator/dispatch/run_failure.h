#pragma once
// Why the run stops, as the log and the engine's error say it: a task that was running on every worker that died
// with it, or that proven workers refused. `task`: the task as JobEncoder::describe names it.

#include <cstddef>
#include <string>

namespace poet {

std::string killed_workers(const std::string& task, int deaths);
// `worker` refused the job starting at `task` (`more_tasks`: the job holds later ones) with `error`; `refusing`
// witnesses did so in all.
std::string refused_by_worker(const std::string& worker, const std::string& task, bool more_tasks,
                              const std::string& error, size_t refusing);
std::string refused_by_workers(const std::string& task, size_t refusing, size_t proven_connected);

}  // namespace poet
