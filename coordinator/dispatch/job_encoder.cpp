#include "coordinator/dispatch/job_encoder.h"

#include "common/formats/rollout_task_proto.h"
#include "common/text/text_format.h"

namespace poet {

void JobEncoder::start_batch(std::span<const RolloutTask> tasks, uint64_t batch_id) {
  clear();
  tasks_ = tasks;
  batch_id_ = batch_id;
  std::unordered_map<const std::vector<double>*, uint64_t> hash_of;  // hashed once per θ, not per task
  for (const RolloutTask& task : tasks) {
    const std::vector<double>* theta = task.theta.get();
    auto [it, fresh] = hash_of.emplace(theta, 0);
    if (fresh) it->second = theta_hash(*theta);
    task_theta_hash_.push_back(it->second);
    thetas_[it->second] = theta;
  }
}

void JobEncoder::clear() {
  tasks_ = {};
  task_theta_hash_.clear();
  thetas_.clear();
  theta_fields_.clear();
}

Outgoing JobEncoder::job(const WorkerId& to, uint64_t job_id, size_t begin, size_t end, std::set<uint64_t>& sent) {
  Outgoing out(to);
  wire::Job& message = *out.message.mutable_job();
  message.set_job_id(job_id);
  message.set_batch_id(batch_id_);
  for (size_t t = begin; t < end; ++t) {
    const uint64_t hash = task_theta_hash_[t];
    if (sent.insert(hash).second) {
      std::shared_ptr<const std::string>& field = theta_fields_[hash];
      if (!field) field = std::make_shared<const std::string>(encode_theta_field(hash, *thetas_.at(hash)));
      out.job_thetas.push_back(field);
    }
    *message.add_tasks() = to_wire(tasks_[t], hash);
  }
  return out;
}

std::string JobEncoder::describe(size_t task) const {
  const RolloutTask& t = tasks_[task];
  std::string text = "task " + std::to_string(task) + " of the batch (course " + t.env.encoding.name + " seed " +
                     std::to_string(t.env.seed) + ", θ " + hex_text(task_theta_hash_.at(task));
  if (t.perturbation)
    text += ", perturbation " + hex_text(t.perturbation->key) + " sign " + std::to_string(t.perturbation->sign);
  return text + ")";
}

}  // namespace poet
