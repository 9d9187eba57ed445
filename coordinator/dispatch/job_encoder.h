#pragma once
// A batch's Jobs as the wire carries them: the batch's θs found by content hash (its tasks share a few), each θ
// encoded once per batch and sent to a worker once per batch (a worker keeps the θs of the batch they came in),
// and a Job of a span of the batch's tasks for one worker. The dispatcher decides who gets which tasks; this says
// how they are written.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <set>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "coordinator/dispatch/outgoing.h"
#include "simulation/rollout_task.h"

namespace poet {

class JobEncoder {
 public:
  // A new batch: `tasks` must outlive it (the dispatcher holds them).
  void start_batch(std::span<const RolloutTask> tasks, uint64_t batch_id);
  void clear();
  uint64_t theta_hash_of(size_t task) const { return task_theta_hash_.at(task); }
  // A task as people read it where it stops the run: its index, course, seed, θ's hash and perturbation.
  std::string describe(size_t task) const;
  // The Job of tasks [begin, end) for a worker; `sent`, the θs that worker was sent in this batch, gains those
  // this Job carries.
  Outgoing job(const WorkerId& to, uint64_t job_id, size_t begin, size_t end, std::set<uint64_t>& sent);

 private:
  std::span<const RolloutTask> tasks_;
  uint64_t batch_id_ = 0;
  std::vector<uint64_t> task_theta_hash_;
  std::unordered_map<uint64_t, const std::vector<double>*> thetas_;                // by hash
  std::unordered_map<uint64_t, std::shared_ptr<const std::string>> theta_fields_;  // by hash, once sent
};

}  // namespace poet
