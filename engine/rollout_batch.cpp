#include "engine/rollout_batch.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "engine/background_pool.h"
#include "simulation/envgen/level_sample.h"
#include "simulation/es/es_gradient.h"
#include "simulation/parallel_for.h"
#include "simulation/rng.h"

namespace poet {
namespace {

int cores() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

}  // namespace

EnvDef RolloutBatch::course(const EnvDef& env, uint64_t key, uint64_t index) const {
  if (!settings_.stochastic) return env;
  // drawn by address from the key of what it is for: the seed first, then (domain randomisation) the encoding
  RandomStream stream(stream_key(key, "course", {index}));
  EnvDef course = env;
  course.seed = static_cast<uint32_t>(stream.uniform_int(0, kMaxEnvSeed));
  if (settings_.random_courses)
    course.encoding = course_of(draw_env_vector(stream, *settings_.random_courses), "random course");
  return course;
}

RolloutTask RolloutBatch::task(SharedParams theta, const EnvDef& env) const {
  RolloutTask t;
  t.theta = std::move(theta);
  t.env = env;
  t.walker = settings_.walker;
  t.max_steps = settings_.max_steps;
  return t;
}

size_t RolloutBatch::add_es_step(const EsRequest& request, int perturbations) {
  Slot slot{tasks_.size(), 2 * static_cast<size_t>(perturbations), {}, request.sigma};
  slot.keys.reserve(static_cast<size_t>(perturbations));
  for (int i = 0; i < perturbations; ++i) {
    const uint64_t key = stream_key(request.step_key, "perturbation", {static_cast<uint64_t>(i)});
    slot.keys.push_back(key);
    const EnvDef env = course(request.env, request.step_key, static_cast<uint64_t>(i));
    for (int sign : {1, -1}) {
      RolloutTask t = task(request.theta, env);
      t.perturbation = Perturbation{key, sign, request.sigma};
      tasks_.push_back(std::move(t));
    }
  }
  slots_.push_back(std::move(slot));
  return slots_.size() - 1;
}

size_t RolloutBatch::add_evaluation(SharedParams theta, const EnvDef& env, uint64_t eval_key) {
  Slot slot{tasks_.size(), static_cast<size_t>(settings_.eval_episodes), {}, 0};
  for (int e = 0; e < settings_.eval_episodes; ++e) {
    tasks_.push_back(task(theta, course(env, eval_key, static_cast<uint64_t>(e))));
  }
  slots_.push_back(std::move(slot));
  return slots_.size() - 1;
}

void RolloutBatch::run(Evaluator& evaluator, RunCounters& counters) {
  early_.clear();
  if (tasks_.empty()) return;  // nothing to ask for: evaluators never see empty batches
  accept(evaluator.evaluate(tasks_), counters);
}

void RolloutBatch::run(Evaluator& evaluator, RunCounters& counters, const EsSettings& es) {
  early_.clear();
  if (tasks_.empty()) return;
  accept(evaluate_early(evaluator, es), counters);
}

size_t RolloutBatch::slot_of(size_t task) const {
  const auto after = std::ranges::upper_bound(slots_, task, {}, &Slot::offset);
  return static_cast<size_t>(after - slots_.begin()) - 1;
}

std::vector<RolloutResult> RolloutBatch::evaluate_early(Evaluator& evaluator, const EsSettings& es) {
  early_.assign(slots_.size(), std::nullopt);
  early_settings_ = es;
  results_.assign(tasks_.size(), RolloutResult{});  // filled as results arrive; never reallocated meanwhile
  std::vector<bool> arrived(tasks_.size(), false);
  std::vector<size_t> missing(slots_.size());
  for (size_t s = 0; s < slots_.size(); ++s) missing[s] = slots_[s].count;

  const auto compute = [this, &es](size_t s) {
    const Slot& slot = slots_[s];
    for (size_t i = slot.offset; i < slot.offset + slot.count; ++i)
      if (!std::isfinite(results_[i].total_reward)) return;  // accept() refuses the batch
    try {
      early_[s] = es_outcome(s, es);
    } catch (...) {
      // es_outcomes computes it again and throws there, as it would have without this early start
    }
  };
  // last of the locals, so that on a throw its destructor joins the threads before anything they read goes
  BackgroundPool pool(cores());
  const ResultsReady ready = [&](size_t first, std::span<const RolloutResult> results) {
    for (size_t k = 0; k < results.size(); ++k) {
      const size_t i = first + k;
      if (i >= tasks_.size() || arrived[i]) continue;
      arrived[i] = true;
      results_[i] = results[k];
      const size_t s = slot_of(i);
      if (--missing[s] == 0 && !slots_[s].keys.empty()) pool.submit([&compute, s] { compute(s); });
    }
  };
  std::vector<RolloutResult> returned = evaluator.evaluate(tasks_, ready);
  pool.wait();

  // an early outcome stands on the results reported; they must be the ones returned
  if (returned.size() == tasks_.size()) {
    for (size_t i = 0; i < tasks_.size(); ++i) {
      if (arrived[i] &&
          std::bit_cast<uint64_t>(returned[i].total_reward) != std::bit_cast<uint64_t>(results_[i].total_reward))
        throw std::runtime_error("evaluator returned a return for task " + std::to_string(i) +
                                 " other than the one it reported final");
    }
  }
  return returned;
}

void RolloutBatch::accept(std::vector<RolloutResult> results, RunCounters& counters) {
  results_ = std::move(results);
  if (results_.size() != tasks_.size())
    throw std::runtime_error("evaluator returned " + std::to_string(results_.size()) + " results for " +
                             std::to_string(tasks_.size()) + " tasks");
  for (const RolloutResult& r : results_) {
    if (!std::isfinite(r.total_reward)) throw std::runtime_error("evaluator returned a non-finite return");
    counters.rollouts += 1;
    counters.env_steps += r.steps;
  }
}

EsOutcome RolloutBatch::es_outcome(size_t handle, const EsSettings& settings) const {
  const Slot& slot = slots_.at(handle);
  const size_t n = slot.keys.size();
  std::vector<double> plus(n), minus(n);
  EsOutcome out;
  out.max_return = results_.at(slot.offset).total_reward;
  for (size_t i = 0; i < n; ++i) {
    plus[i] = results_[slot.offset + 2 * i].total_reward;
    minus[i] = results_[slot.offset + 2 * i + 1].total_reward;
    out.mean_return += plus[i] + minus[i];
    out.max_return = std::max({out.max_return, plus[i], minus[i]});
  }
  out.mean_return /= static_cast<double>(2 * n);
  const size_t dim = tasks_.at(slot.offset).theta->size();
  out.gradient = es_gradient(slot.keys, plus, minus, slot.sigma, settings.normalize_grads_by_sigma, dim);
  return out;
}

std::vector<EsOutcome> RolloutBatch::es_outcomes(std::span<const size_t> handles, const EsSettings& settings) const {
  std::vector<EsOutcome> out(handles.size());
  const bool early = !early_.empty() && settings == early_settings_;
  parallel_for(static_cast<int>(handles.size()), cores(), [&](int i) {
    const size_t h = handles[static_cast<size_t>(i)];
    out[static_cast<size_t>(i)] = early && early_.at(h) ? *early_[h] : es_outcome(h, settings);
  });
  return out;
}

Evaluation RolloutBatch::evaluation(size_t handle) const {
  const Slot& slot = slots_.at(handle);
  Evaluation e;
  e.finished = true;
  e.steps = results_.at(slot.offset).steps;
  for (size_t i = 0; i < slot.count; ++i) {
    const RolloutResult& r = results_[slot.offset + i];
    e.score += r.total_reward;
    e.finished = e.finished && r.finished;
  }
  e.score /= static_cast<double>(slot.count);
  return e;
}

int64_t RolloutBatch::env_steps(size_t handle) const {
  const Slot& slot = slots_.at(handle);
  int64_t steps = 0;
  for (size_t i = 0; i < slot.count; ++i) steps += results_.at(slot.offset + i).steps;
  return steps;
}

}  // namespace poet
