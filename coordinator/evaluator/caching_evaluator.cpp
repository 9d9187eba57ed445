#include "coordinator/evaluator/caching_evaluator.h"

#include <stdexcept>
#include <string>
#include <utility>

#include "common/formats/rollout_task_proto.h"

namespace poet {

std::vector<RolloutResult> CachingEvaluator::evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) {
  std::vector<RolloutResult> results(tasks.size());
  std::vector<size_t> forwarded;                 // the tasks the inner evaluator runs, in task order
  std::vector<std::string> forwarded_keys;       // each one's key (empty: not to be remembered)
  std::vector<std::vector<size_t>> repeats;      // per forwarded task, the later tasks of this batch equal to it
  std::vector<size_t> known;                     // tasks answered from memory
  std::unordered_map<std::string, size_t> runs;  // key → position in forwarded, for repeats within the batch
  std::unordered_map<const std::vector<double>*, uint64_t> theta_hashes;  // θ is shared by many tasks of a batch
  auto forward = [&](size_t i, std::string key) {
    forwarded.push_back(i);
    forwarded_keys.push_back(std::move(key));
    repeats.emplace_back();
  };
  for (size_t i = 0; i < tasks.size(); ++i) {
    const RolloutTask& task = tasks[i];
    if (task.perturbation || !task.theta) {  // never repeated (or not runnable: the inner evaluator says why)
      forward(i, {});
      continue;
    }
    auto [hash, fresh] = theta_hashes.try_emplace(task.theta.get(), 0);
    if (fresh) hash->second = theta_hash(*task.theta);
    std::string key = to_wire(task, hash->second).SerializeAsString();
    if (const auto hit = results_.find(key); hit != results_.end()) {
      results[i] = hit->second;
      known.push_back(i);
      continue;
    }
    if (const auto same = runs.find(key); same != runs.end()) {
      repeats[same->second].push_back(i);
      continue;
    }
    runs.emplace(key, forwarded.size());
    forward(i, std::move(key));
  }
  for (const size_t i : known) {
    episodes_saved_ += 1;
    steps_saved_ += results[i].steps;
    if (ready) ready(i, std::span<const RolloutResult>(&results[i], 1));
  }

  std::vector<RolloutTask> inner_tasks;
  inner_tasks.reserve(forwarded.size());
  for (const size_t i : forwarded) inner_tasks.push_back(tasks[i]);
  ResultsReady inner_ready;
  if (ready) {
    inner_ready = [&](size_t first, std::span<const RolloutResult> done) {
      for (size_t j = 0; j < done.size(); ++j) {
        ready(forwarded[first + j], done.subspan(j, 1));
        for (const size_t same : repeats[first + j]) ready(same, done.subspan(j, 1));
      }
    };
  }
  const std::vector<RolloutResult> ran =
      inner_tasks.empty() ? std::vector<RolloutResult>{} : inner_.evaluate(inner_tasks, inner_ready);
  if (ran.size() != forwarded.size())
    throw std::runtime_error("the evaluator returned " + std::to_string(ran.size()) + " results for " +
                             std::to_string(forwarded.size()) + " tasks");
  for (size_t p = 0; p < forwarded.size(); ++p) {
    results[forwarded[p]] = ran[p];
    for (const size_t same : repeats[p]) {
      results[same] = ran[p];
      episodes_saved_ += 1;
      steps_saved_ += ran[p].steps;
    }
    if (!forwarded_keys[p].empty() && !ran[p].stopped) remember(std::move(forwarded_keys[p]), ran[p]);
  }
  return results;
}

void CachingEvaluator::remember(std::string key, const RolloutResult& result) {
  if (cost(key) > max_bytes_) return;
  RolloutResult kept = result;
  kept.trajectory.clear();
  if (!results_.emplace(key, std::move(kept)).second) return;
  bytes_ += cost(key);
  order_.push_back(std::move(key));
  while (bytes_ > max_bytes_) {
    bytes_ -= cost(order_.front());
    results_.erase(order_.front());
    order_.pop_front();
  }
}

void CachingEvaluator::went_back(uint64_t last_batch) {
  clear();
  inner_.went_back(last_batch);
}

void CachingEvaluator::clear() {
  results_.clear();
  order_.clear();
  bytes_ = 0;
}

}  // namespace poet
