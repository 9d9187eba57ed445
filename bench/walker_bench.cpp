// Throughput of the walker domain on one core: bare Box2D stepping vs full rollouts (policy, lidar, reward)
// along the same episodes, and the cost of a reset. Run: build/bench/walker_bench (see bench/README.md).

#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <vector>

#include "common/formats/policy/policy_file.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"
#include "simulation/rollout.h"
#include "simulation/walker/terrain.h"
#include "simulation/walker/walker_env.h"

namespace poet {
namespace {

// 128 episodes per course: builds of other last bits (the C library's math in walker_bench_libm) walk other
// episodes, and a set of 16 random policies' falls costs up to 4 % more or less in one build than in the other by
// its contacts alone (BM_RolloutSet below); over 128 that is within 1 %.
constexpr int kPolicies = 128;
constexpr int kSetSize = 16;

EnvDef course_def(const std::string& name) { return {*named_course(name), 17}; }

// The same 128 random initial policies (θ ~ N(0, 0.1²)) on each course, with the actions each took, so that the
// bare-physics benchmark replays exactly the episodes the full rollouts run.
struct Workload {
  Terrain terrain;
  std::vector<Mlp> policies;
  std::vector<std::vector<Action>> actions;
  int64_t steps = 0;
};

const Workload& workload(const std::string& name) {
  static std::map<std::string, Workload> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  Workload w{Terrain::generate(course_def(name)), {}, {}, 0};
  for (int p = 0; p < kPolicies; ++p) {
    RandomStream rng(stream_key(2024, "bench-policy", {uint64_t(p)}));
    w.policies.emplace_back(random_params(rng));
    WalkerEnv env(w.terrain);
    const Observation* obs = &env.reset();
    std::vector<Action> acts;
    for (int k = 0; k < walker::kDefaultTimeLimit; ++k) {
      acts.push_back(w.policies.back().act(*obs));
      if (env.step(acts.back()).done()) break;
      obs = &env.observation();
    }
    w.steps += int64_t(acts.size());
    w.actions.push_back(std::move(acts));
  }
  return cache.emplace(name, std::move(w)).first->second;
}

// (a) Box2D alone: build the world, then only motor settings and world steps along the recorded actions.
void BM_BarePhysics(benchmark::State& state, const std::string& name) {
  const Workload& w = workload(name);
  for (auto _ : state) {
    for (const auto& acts : w.actions) {
      WalkerEnv env(w.terrain);
      env.reset();
      for (const Action& a : acts) env.advance(a);
      benchmark::DoNotOptimize(env.hull_x());
    }
  }
  state.SetItemsProcessed(state.iterations() * w.steps);
  state.counters["steps_per_s"] = benchmark::Counter(double(w.steps), benchmark::Counter::kIsIterationInvariantRate);
}

// Full rollouts of the workload's policies [first, end): reset, policy, lidar, observation, reward, termination.
void roll_out(benchmark::State& state, const Workload& w, size_t first, size_t end) {
  int64_t expected = 0;
  for (size_t p = first; p < end; ++p) expected += int64_t(w.actions[p].size());
  int64_t steps = 0;
  for (auto _ : state) {
    steps = 0;
    for (size_t p = first; p < end; ++p) steps += rollout(w.policies[p], w.terrain).steps;
  }
  if (steps != expected) state.SkipWithError("rollouts diverged from the recorded episodes");
  state.SetItemsProcessed(state.iterations() * expected);
  state.counters["steps_per_s"] = benchmark::Counter(double(expected), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["steps"] = double(expected);  // the episodes' length: builds of other last bits walk other episodes
}

// (b) Full rollouts of the same policies.
void BM_Rollout(benchmark::State& state, const std::string& name) {
  const Workload& w = workload(name);
  roll_out(state, w, 0, w.policies.size());
}

// (b'') BM_Rollout/flat's policies in their eight sets of 16: how much one set's episodes weigh in a comparison
// between builds that compute other last bits.
void BM_RolloutSet(benchmark::State& state) {
  const auto first = static_cast<size_t>(state.range(0)) * kSetSize;
  roll_out(state, workload("flat"), first, first + kSetSize);
}

// (b') A trained walker's rollouts: the shipped flat walker on flat and r1, terrain seeds 0–7 — long episodes of a
// regular gait, where builds of other last bits walk nearly the same contacts (random policies' falls differ more).
void BM_WalkerRollout(benchmark::State& state, const std::string& name) {
  static const Expected<PolicyFile> walker = load_policy(POET_SOURCE_DIR "/data/walkers/flat-walker.json");
  if (!walker) {
    state.SkipWithError(walker.error().c_str());
    return;
  }
  const Mlp policy(walker->params);
  std::vector<Terrain> courses;
  for (uint32_t seed = 0; seed < 8; ++seed) courses.push_back(Terrain::generate({*named_course(name), seed}));
  int64_t steps = 0;
  for (auto _ : state) {
    steps = 0;
    for (const Terrain& course : courses) steps += rollout(policy, course).steps;
  }
  state.SetItemsProcessed(state.iterations() * steps);
  state.counters["steps_per_s"] = benchmark::Counter(double(steps), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["steps"] = double(steps);
}

// The peers' workload (STATISTICS.md): uniformly random actions, a reset whenever an episode ends. With
// `with_policy` the policy is also evaluated on every observation (its answer discarded), so the figure includes
// everything a rollout computes; without it, this is the environment alone, as the peers measured theirs.
void BM_RandomActions(benchmark::State& state, const std::string& name, bool physics_only, bool with_policy) {
  const Terrain terrain = Terrain::generate(course_def(name));
  RandomStream policy_rng(stream_key(1, "bench-policy"));
  const Mlp policy(random_params(policy_rng));
  constexpr int kSteps = 20000;
  for (auto _ : state) {
    RandomStream rng(stream_key(5, "bench-actions"));
    WalkerEnv env(terrain);
    env.reset();
    for (int k = 0; k < kSteps; ++k) {
      const Action a = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
      if (physics_only) {
        env.advance(a);
        // ends where the full step would: the same episodes, so both rows step the same trajectories
        if (env.hull_x() < 0 || env.hull_touched() || env.hull_x() > walker::kFinishX) env.reset();
        continue;
      }
      if (with_policy) benchmark::DoNotOptimize(policy.act(env.observation()));
      if (env.step(a).done()) env.reset();
    }
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}

// (c) The cost of a reset, in its two parts: drawing the course, and building a world from it plus the reset step.
void BM_GenerateCourse(benchmark::State& state, const std::string& name) {
  const EnvDef def = course_def(name);
  for (auto _ : state) benchmark::DoNotOptimize(Terrain::generate(def));
}

void BM_ResetWorld(benchmark::State& state, const std::string& name) {
  const Terrain terrain = Terrain::generate(course_def(name));
  for (auto _ : state) {
    WalkerEnv env(terrain);
    benchmark::DoNotOptimize(env.reset());
  }
}

void BM_Policy(benchmark::State& state) {
  RandomStream rng(stream_key(1, "bench"));
  const Mlp policy(random_params(rng));
  Observation obs{};
  for (double& v : obs) v = rng.uniform(-1, 1);
  for (auto _ : state) {
    benchmark::DoNotOptimize(policy.act(obs));
    obs[0] += 1e-9;
  }
}

BENCHMARK_CAPTURE(BM_BarePhysics, flat, std::string("flat"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rollout, flat, std::string("flat"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BarePhysics, hard, std::string("hard"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rollout, hard, std::string("hard"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rollout, r1, std::string("r1"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rollout, hardcore_like, std::string("hardcore-like"))->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RolloutSet)->ArgName("flat_set")->DenseRange(0, kPolicies / kSetSize - 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WalkerRollout, flat, std::string("flat"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WalkerRollout, r1, std::string("r1"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RandomActions, bare_flat, std::string("r1"), true, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RandomActions, env_flat, std::string("r1"), false, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RandomActions, env_policy_flat, std::string("r1"), false, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RandomActions, bare_hard, std::string("hardcore-like"), true, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RandomActions, env_hard, std::string("hardcore-like"), false, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RandomActions, env_policy_hard, std::string("hardcore-like"), false, true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GenerateCourse, flat, std::string("flat"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_GenerateCourse, hard, std::string("hard"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ResetWorld, flat, std::string("flat"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ResetWorld, hard, std::string("hard"))->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Policy);

}  // namespace
}  // namespace poet
