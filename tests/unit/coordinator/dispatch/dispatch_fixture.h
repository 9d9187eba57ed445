#pragma once
// What the Dispatcher's tests share: a batch of tasks, Hellos of local workers and of strangers, the honest answer
// to a job (reward = the task's course seed, so results show their task), the coordinator's own results for a check,
// and settings with a fake clock's timings.

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coordinator/dispatch/dispatcher.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet::dispatch_fixture {

inline std::vector<RolloutTask> batch(size_t n) {
  RandomStream init(stream_key(3, "dispatcher-test"));
  auto theta = std::make_shared<const std::vector<double>>(random_params(init));
  std::vector<RolloutTask> tasks;
  for (size_t i = 0; i < n; ++i) {
    RolloutTask t;
    t.theta = theta;
    t.env = EnvDef{named_course("flat").value(), static_cast<uint32_t>(i)};
    t.perturbation = Perturbation{100 + i, i % 2 ? -1 : 1, 0.1};
    tasks.push_back(t);
  }
  return tasks;
}

inline wire::Hello hello(uint32_t threads = 1, uint64_t fingerprint = 42) {
  wire::Hello h;
  h.set_protocol_version(wire::PROTOCOL_VERSION);
  h.set_fingerprint_digest(fingerprint);
  h.set_threads(threads);
  h.set_name("test");
  h.set_local_token("local");  // proven from the start, as a local worker: the rules for others are tested below
  return h;
}

// A worker's Hello and the Heartbeat that answers its Welcome: from then on it gets jobs.
// `key`: the CURVE key it connected with (empty: none, as without CURVE).
inline void join(Dispatcher& d, const WorkerId& id, const wire::Hello& h, Millis now, const std::string& key = {}) {
  ASSERT_TRUE(d.on_hello(id, h, now, key).has_welcome());
  ASSERT_TRUE(d.heard_from(id, now));
}

// Whether a worker is connected, as the status socket shows it.
inline bool connected(const Dispatcher& d, const WorkerId& id) {
  const std::vector<WorkerView> workers = d.workers();
  return std::any_of(workers.begin(), workers.end(), [&](const WorkerView& w) { return w.id == id; });
}

// The rollback the referee asks for, taken as the run loop takes it: it goes back to before that batch.
inline std::optional<uint64_t> take_rollback(Dispatcher& d) {
  const std::optional<uint64_t> asked = d.referee().rollback_asked();
  if (asked) d.went_back(*asked - 1);
  return asked;
}

// The answer a worker gives to a job: reward = the task's course seed, so results show their task.
inline wire::Result answer(const wire::Job& job) {
  wire::Result r;
  r.set_job_id(job.job_id());
  for (const wire::Task& t : job.tasks()) {
    wire::TaskResult* result = r.add_results();
    result->set_total_reward(t.env().seed());
    result->set_steps(10);
  }
  return r;
}

inline std::vector<Outgoing> jobs_in(const std::vector<Outgoing>& out) {
  std::vector<Outgoing> jobs;
  for (const Outgoing& o : out)
    if (o.message.has_job()) jobs.push_back(o);
  return jobs;
}

inline DispatchSettings settings() {
  DispatchSettings s;
  s.heartbeat_ms = 100;
  s.liveness_ms = 500;
  s.build.fingerprint_digest = 42;
  s.local_token = "local";
  return s;
}

// Jobs of one task each, however the batch would be cut.
inline DispatchSettings one_task_jobs() {
  DispatchSettings s = settings();
  s.max_chunk = 1;
  return s;
}

// Settings under which every job answered by a worker that is not local is checked by another.
inline DispatchSettings checking_every_job() {
  DispatchSettings s = settings();
  s.verify_fraction = 1;
  return s;
}

inline wire::Hello stranger_hello(const std::string& name) {
  wire::Hello h = hello();
  h.clear_local_token();
  h.set_name(name);
  return h;
}

// The coordinator's own results for a job it checks: the honest ones (answer()).
inline std::vector<RolloutResult> coordinators_results(const Dispatcher::CoordinatorCheck& check) {
  std::vector<RolloutResult> own;
  for (const RolloutTask& task : check.tasks) {
    RolloutResult r;
    r.total_reward = double(task.env.seed);
    r.steps = 10;
    own.push_back(r);
  }
  return own;
}

}  // namespace poet::dispatch_fixture
