#pragma once
// How a batch is cut into jobs: tasks per job, from the batch's size and the workers that may be sent jobs.

#include <cstddef>
#include <vector>

namespace poet {

// `threads`: of each worker that may be sent jobs (ready, not demoted); `jobs_ahead`: jobs a worker holds at once;
// at least 1 and at most `max_chunk` tasks a job.
size_t tasks_per_job(size_t tasks, const std::vector<int>& threads, int jobs_ahead, int max_chunk);

}  // namespace poet
