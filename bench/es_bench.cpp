// The cost of an ES step (spec §2) through the engine's own path — tasks in a RolloutBatch, the LocalEvaluator,
// the gradient and Adam — on a fixed course: wall time on 1 and 2 threads, the parallel efficiency, and the
// coordinator's share (rebuilding noise, ranks, gradient, Adam) against the rollouts. Ratios are measured within
// one run. Run: build/bench/es_bench (see bench/README.md).

#include <benchmark/benchmark.h>

#include <chrono>

#include "coordinator/evaluator/local_evaluator.h"
#include "engine/rollout_batch.h"
#include "es_step_fixture.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/es/optimizer.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {
namespace {

using Fixture = EsStepFixture;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct StepTimes {
  double rollouts = 0;     // seconds in the evaluator
  double coordinator = 0;  // seconds rebuilding noise, ranking, gradient, Adam
  int64_t env_steps = 0;
};

// One ES step of the fixture's pair; `step` varies the noise like successive iterations do.
StepTimes es_step(Fixture& f, Evaluator& evaluator, uint64_t step) {
  StepTimes times;
  RunCounters counters;
  RolloutBatch batch(f.episodes);
  const size_t handle = f.add_step(batch, step);
  auto t0 = Clock::now();
  batch.run(evaluator, counters);
  times.rollouts = seconds_since(t0);
  t0 = Clock::now();
  OptimizerState opt = fresh_optimizer(f.es, f.theta.size());
  std::vector<double> theta = f.theta;
  const EsOutcome out = batch.es_outcome(handle, f.es);
  adam_step(theta, out.gradient, opt, f.es);
  decay(opt, f.es);
  benchmark::DoNotOptimize(theta.data());
  times.coordinator = seconds_since(t0);
  times.env_steps = counters.env_steps;
  return times;
}

// Wall time of an ES step on N threads.
void BM_EsStep(benchmark::State& state) {
  Fixture f;
  LocalEvaluator evaluator(static_cast<int>(state.range(0)));
  uint64_t step = 0;
  int64_t env_steps = 0;
  for (auto _ : state) env_steps += es_step(f, evaluator, step++ % 4).env_steps;
  state.counters["env_steps/s"] = benchmark::Counter(double(env_steps), benchmark::Counter::kIsRate);
  state.counters["rollouts"] = 2 * Fixture::kPerturbations;
}
BENCHMARK(BM_EsStep)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(4);

// Within one run: the same steps on 1 and 2 threads (efficiency = T1 / (2·T2)), and the coordinator's work as a
// share of the rollout time on one thread.
void BM_EsStepRatios(benchmark::State& state) {
  Fixture f;
  LocalEvaluator one(1), two(2);
  double t1 = 0, t2 = 0, coordinator = 0, rollouts = 0;
  uint64_t step = 0;
  for (auto _ : state) {
    const StepTimes a = es_step(f, one, step % 4);
    const StepTimes b = es_step(f, two, step % 4);
    ++step;
    t1 += a.rollouts + a.coordinator;
    t2 += b.rollouts + b.coordinator;
    coordinator += a.coordinator;
    rollouts += a.rollouts;
  }
  state.counters["parallel_efficiency"] = t1 / (2 * t2);
  state.counters["coordinator_share"] = coordinator / rollouts;
}
BENCHMARK(BM_EsStepRatios)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(4);

// An evaluator that returns at once (returns from a hash of the task), so only the coordinator's work is timed.
class InstantEvaluator final : public Evaluator {
 public:
  using Evaluator::evaluate;
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady&) override {
    std::vector<RolloutResult> out(tasks.size());
    for (size_t i = 0; i < tasks.size(); ++i) {
      const uint64_t h = mix64(tasks[i].perturbation ? tasks[i].perturbation->key + 3 * i : i);
      out[i].total_reward = static_cast<double>(h >> 40) / 1e5;
      out[i].steps = 100;
    }
    return out;
  }
};

// The gradients of one target's transfer round at the paper's sizes: 19 source pairs, 256 mirrored perturbations
// (512 rollouts) each. Arg 0: one after another (es_outcome); arg 1: es_outcomes, spread over the cores. The
// numbers are the same either way (golden_test pins them); this measures the coordinator's serial time.
void BM_TransferGradients(benchmark::State& state) {
  Fixture f;
  InstantEvaluator evaluator;
  RunCounters counters;
  RolloutBatch batch(f.episodes);
  std::vector<size_t> handles;
  for (uint64_t source = 0; source < 19; ++source)
    handles.push_back(
        batch.add_es_step({share(f.theta), f.env, 0.1, stream_key(2024, "bench-transfer", {source})}, 256));
  batch.run(evaluator, counters);
  for (auto _ : state) {
    if (state.range(0) == 0) {
      for (size_t h : handles) benchmark::DoNotOptimize(batch.es_outcome(h, f.es).gradient.data());
    } else {
      benchmark::DoNotOptimize(batch.es_outcomes(handles, f.es).data());
    }
  }
  state.counters["gradients_per_s"] =
      benchmark::Counter(static_cast<double>(handles.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_TransferGradients)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace poet
