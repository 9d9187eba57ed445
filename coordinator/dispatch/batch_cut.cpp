#include "coordinator/dispatch/batch_cut.h"

#include <algorithm>
#include <numeric>

namespace poet {

size_t tasks_per_job(size_t tasks, const std::vector<int>& threads, int jobs_ahead, int max_chunk) {
  const size_t total_threads = static_cast<size_t>(std::accumulate(threads.begin(), threads.end(), 0L));
  const size_t workers = threads.size();
  const auto ceil_div = [](size_t a, size_t b) { return (a + b - 1) / b; };
  // About four jobs per thread of the workers present, so that a slow or lost worker delays little. But a batch
  // that goes out whole at once (jobs_ahead jobs a worker) is not balanced by its queue: there, one job a worker
  // ends no later and costs the coordinator half the messages or fewer.
  size_t per_job = ceil_div(tasks, 4 * std::max<size_t>(total_threads, 1));
  if (workers > 0 && ceil_div(tasks, per_job) <= static_cast<size_t>(jobs_ahead) * workers)
    per_job = ceil_div(tasks, workers);
  return std::clamp<size_t>(per_job, 1, static_cast<size_t>(max_chunk));
}

}  // namespace poet
