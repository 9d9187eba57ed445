// The coordinator's own work at the paper's sizes against the time its batches' rollouts take on 256 workers,
// through the engine's real steps on a state of 20 active pairs with the paper preset: an optimisation step (20
// ES steps of 512 rollouts, then their evaluations) and a transfer round (380 proposal ES steps with the direct
// evaluations, then the proposals' evaluations). No episode runs: PacedEvaluator stands for 256 single-threaded
// workers and hands out synthetic results at the moments those workers would finish them. Arg 1 reports results
// as they finish (gradients start while the batch runs); arg 0 only at the end of each batch (the gradients
// follow it). Run: build/bench/coordinator_bench (see bench/README.md).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <functional>
#include <numeric>
#include <queue>
#include <thread>

#include "engine/engine.h"
#include "engine/iteration_context.h"
#include "run_directory/config/run_config.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {
namespace {

constexpr int kWorkers = 256;               // the paper's cores
constexpr double kStepsPerSecond = 23'000;  // one core: walker_bench BM_Rollout on the bench machine
constexpr double kTick = 0.002;             // seconds between deliveries of results

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Half the episodes run to the time limit, the others end at a uniform step in [50, limit): 1,512 steps on average
// with the paper's 2,000-step limit. Returns are uniform in [-100, 300). Both from a hash of what the task runs.
RolloutResult synthetic_result(const RolloutTask& task) {
  uint64_t h = mix64(std::bit_cast<uint64_t>((*task.theta)[0]) ^ mix64(task.env.seed));
  if (task.perturbation) h = mix64(h ^ task.perturbation->key ^ (task.perturbation->sign > 0 ? 1u : 2u));
  RolloutResult r;
  const uint64_t limit = static_cast<uint64_t>(task.max_steps);
  r.steps = static_cast<int>((h >> 63) ? limit : 50 + (h >> 20) % (limit - 50));
  r.total_reward = -100.0 + 400.0 * static_cast<double>(h & 0xfffff) / double(1 << 20);
  return r;
}

// 256 workers take the tasks in order, each the next one when it is free, and a task takes its steps at
// kStepsPerSecond. Results are released (through `ready` when reporting) as wall-clock time reaches their
// finish, and the batch returns at the last one.
class PacedEvaluator final : public Evaluator {
 public:
  explicit PacedEvaluator(bool report) : report_(report) {}
  using Evaluator::evaluate;
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override {
    const Clock::time_point t0 = Clock::now();
    std::vector<RolloutResult> results(tasks.size());
    std::vector<double> finish(tasks.size());  // seconds after t0
    std::priority_queue<double, std::vector<double>, std::greater<>> free_at;
    for (int w = 0; w < kWorkers; ++w) free_at.push(0.0);
    for (size_t i = 0; i < tasks.size(); ++i) {
      results[i] = synthetic_result(tasks[i]);
      finish[i] = free_at.top() + results[i].steps / kStepsPerSecond;
      free_at.pop();
      free_at.push(finish[i]);
    }
    std::vector<size_t> order(tasks.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::ranges::stable_sort(order, {}, [&](size_t i) { return finish[i]; });

    // a wake-up every kTick at most, as a dispatcher takes results in bursts; the last one on time
    const double makespan = finish[order.back()];
    for (size_t k = 0; k < order.size();) {
      const double wake = std::min(std::max(finish[order[k]], seconds_since(t0) + kTick), makespan);
      std::this_thread::sleep_until(t0 + std::chrono::duration<double>(wake));
      const double now = seconds_since(t0);
      size_t end = k + 1;
      while (end < order.size() && finish[order[end]] <= now) ++end;
      if (report_ && ready)
        for (size_t j = k; j < end; ++j) ready(order[j], std::span(&results[order[j]], 1));
      k = end;
    }
    rollout_seconds += makespan;
    inside_seconds += seconds_since(t0);
    return results;
  }

  double rollout_seconds = 0;  // the batches' makespans on the 256 workers
  double inside_seconds = 0;   // wall time in evaluate()

 private:
  bool report_;
};

// The paper preset's state at its first transfer round (iteration 25, no reproduction): active_cap pairs (20) on
// distinct environments, with distinct θs and fresh optimizers.
RunState paper_state() {
  RunState state = initial_state(run_settings(load_run_config(POET_PAPER_CONFIG).value()));
  const EsSettings& es = state.settings.es;
  for (int i = 1; i < state.settings.poet.active_cap; ++i) {
    Pair p;
    p.id = state.next_pair_id++;
    p.env = EnvDef{named_course("flat").value(), static_cast<uint32_t>(1000 + i)};
    p.env.encoding.roughness = 0.3 * i;
    p.env.encoding.name = "bench" + std::to_string(i);
    RandomStream init(stream_key(state.settings.seed, "bench-pair", {static_cast<uint64_t>(i)}));
    p.theta = random_params(init, 0.1);
    p.best_theta = p.theta;
    p.optimizer = fresh_optimizer(es, p.theta.size());
    state.pairs.push_back(std::move(p));
  }
  state.next_iteration = state.settings.poet.transfer_interval;
  return state;
}

// Runs one engine step on a fresh paper state through a PacedEvaluator; counters: the rollouts and their mean
// length, their time on 256 workers (the batches' makespans), the wall time and its part outside evaluate(),
// and the coordinator's share = (wall − rollout time) / rollout time.
void run_paced(benchmark::State& bench, void (*step)(IterationContext&)) {
  double rollout_s = 0, wall_s = 0, between_s = 0;
  int64_t rollouts = 0, env_steps = 0;
  for (auto _ : bench) {
    bench.PauseTiming();
    RunState state = paper_state();
    PacedEvaluator evaluator(bench.range(0) == 1);
    IterationReport report;
    IterationContext ctx = iteration_context(state, evaluator, report);
    bench.ResumeTiming();
    const Clock::time_point t0 = Clock::now();
    step(ctx);
    const double wall = seconds_since(t0);
    wall_s += wall;
    rollout_s += evaluator.rollout_seconds;
    between_s += wall - evaluator.inside_seconds;
    rollouts += state.counters.rollouts;
    env_steps += state.counters.env_steps;
  }
  const double n = static_cast<double>(bench.iterations());
  bench.counters["rollouts"] = static_cast<double>(rollouts) / n;
  bench.counters["steps_per_rollout"] = static_cast<double>(env_steps) / static_cast<double>(rollouts);
  bench.counters["rollout_s"] = rollout_s / n;
  bench.counters["wall_s"] = wall_s / n;
  bench.counters["between_batches_s"] = between_s / n;
  bench.counters["coordinator_share"] = (wall_s - rollout_s) / rollout_s;
}

void BM_OptimisationStep(benchmark::State& bench) { run_paced(bench, optimise); }
BENCHMARK(BM_OptimisationStep)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

void BM_TransferRound(benchmark::State& bench) { run_paced(bench, transfer); }
BENCHMARK(BM_TransferRound)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace poet
