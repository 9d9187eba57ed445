// Golden numbers: a fixed small POET run and a set of single rollouts, pinned by digest. Box2D's determinism
// test pins a hash the same way. These fail when the simulation or the ES changes behaviour — on purpose or
// not — and say so: a run's numbers are a function of its config only while they pass, and a checkpoint written
// before such a change would resume differently after it.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <string>
#include <vector>

#include "common/program/build_fingerprint.h"
#include "coordinator/evaluator/caching_evaluator.h"
#include "coordinator/evaluator/local_evaluator.h"
#include "engine/engine.h"
#include "engine_test_support.h"
#include "run_directory/files/checkpoint.h"
#include "run_directory/files/checkpoint_file.h"
#include "simulation/arithmetic_probe.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"
#include "simulation/rollout.h"

namespace poet {
namespace {

// Update only for an intended change of behaviour, with the reason in the commit message.
constexpr uint64_t kRolloutsDigest = 0xd97086d9511aff55;
constexpr uint64_t kCheckpointDigest = 0x995ba5556c7c2813;
constexpr uint64_t kCppnCheckpointDigest = 0x28a15c2898c30ba1;
constexpr uint64_t kPataEcCheckpointDigest = 0x3fc8cf41f5187b6d;
constexpr uint64_t kArithmeticDigest = 0x1a71b8c3ee2a10e5;  // simulation/arithmetic_probe.h, on every machine

// FNV-1a: a fixed, documented function of the bytes, whatever the platform's std::hash does.
uint64_t fnv1a(std::string_view bytes) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (char c : bytes) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
  return h;
}

std::string hex(uint64_t value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "0x%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

std::string changed(const std::string& what, uint64_t got, uint64_t pinned) {
  return what + " changed behaviour: digest " + hex(got) + ", pinned " + hex(pinned) +
         ". Every run's numbers now differ from earlier builds' (and a checkpoint from one would resume "
         "differently). If the change is intended, pin the new digest and say why in the commit.\nThis build:\n" +
         build_fingerprint();
}

// What the machine computes: the project's math, Box2D and the walker over fixed inputs. The same on every
// processor, C library and architecture the project supports (tests/integration/masked_processor_test.cpp and
// tests/crossmachine run this suite there).
TEST(Golden, ArithmeticProbe) {
  const ArithmeticProbe probe = probe_arithmetic();
  EXPECT_EQ(probe.digest(), kArithmeticDigest)
      << changed("what this machine computes (math " + hex(probe.math) + ", box2d " + hex(probe.box2d) + ", walker " +
                     hex(probe.walker) + ")",
                 probe.digest(), kArithmeticDigest);
}

TEST(Golden, SingleRolloutReturns) {
  std::string bits;
  std::string table;
  for (const char* course : {"flat", "r1", "hard", "hardcore-like"}) {
    for (uint32_t seed : {0u, 17u}) {
      for (uint64_t policy : {1u, 2u}) {
        RandomStream init(stream_key(policy, "golden"));
        const RolloutResult r = rollout(random_params(init), EnvDef{named_course(course).value(), seed});
        const uint64_t reward = std::bit_cast<uint64_t>(r.total_reward);
        bits.append(reinterpret_cast<const char*>(&reward), sizeof reward);
        bits += std::to_string(r.steps) + (r.finished ? "F" : "") + (r.fell ? "X" : "");
        char line[128];
        std::snprintf(line, sizeof line, "  %-14s seed %-3u policy %llu: %.17g over %d steps\n", course, seed,
                      static_cast<unsigned long long>(policy), r.total_reward, r.steps);
        table += line;
      }
    }
  }
  const uint64_t digest = fnv1a(bits);
  EXPECT_EQ(digest, kRolloutsDigest) << changed("the walker simulation", digest, kRolloutsDigest) << table;
}

// Five iterations of a small run; its checkpoint's digest against the pinned one. Run twice: on threads, and as the
// coordinator runs it, behind the score cache — which must change nothing but the episodes run (and must save some:
// a pair's θ on its own course in the transfer round, right after its evaluation).
void expect_checkpoint_digest(const pb::RunConfig& config, uint64_t pinned, const char* what) {
  pb::RunConfig c = config;
  c.set_iterations(5);
  for (const bool cached : {false, true}) {
    RunState s = initial_state(run_settings(c));
    LocalEvaluator threads(2);
    CachingEvaluator cache(threads, kScoreCacheBytes);
    Evaluator& evaluator = cached ? static_cast<Evaluator&>(cache) : threads;
    while (!run_complete(s)) run_iteration(s, evaluator);
    ASSERT_GE(s.pairs.size(), 3u);  // reproduction and transfer ran
    ASSERT_GT(s.counters.transfer_attempts, 0);
    const uint64_t digest = fnv1a(encode_checkpoint_file(to_checkpoint(c, s)));
    EXPECT_EQ(digest, pinned) << (cached ? "behind the score cache: " : "") << changed(what, digest, pinned) << "pairs "
                              << s.pairs.size() << ", rollouts " << s.counters.rollouts << ", env steps "
                              << s.counters.env_steps;
    if (cached) {
      EXPECT_GT(cache.episodes_saved(), 0);
      std::printf("%s: the score cache answered %lld of %lld rollouts (%lld of %lld environment steps)\n", what,
                  static_cast<long long>(cache.episodes_saved()), static_cast<long long>(s.counters.rollouts),
                  static_cast<long long>(cache.steps_saved()), static_cast<long long>(s.counters.env_steps));
    }
  }
}

TEST(Golden, SmallRunCheckpoint) {
  expect_checkpoint_digest(testing::small_real_run(), kCheckpointDigest,
                           "the ES or the POET loop (or the simulation under it)");
}

TEST(Golden, SmallCppnRunCheckpoint) {
  expect_checkpoint_digest(testing::small_cppn_run(), kCppnCheckpointDigest,
                           "CPPN terrain, its mutation, or the POET loop (or the simulation under it)");
}

// The same run with PATA-EC novelty, whose characterisations add evaluations and change which children go first.
TEST(Golden, SmallPataEcRunCheckpoint) {
  pb::RunConfig c = testing::small_pata_ec_run();
  c.set_iterations(5);
  for (const bool cached : {false, true}) {  // PATA-EC asks most often for scores it knows
    RunState s = initial_state(run_settings(c));
    LocalEvaluator threads(2);
    CachingEvaluator cache(threads, kScoreCacheBytes);
    Evaluator& evaluator = cached ? static_cast<Evaluator&>(cache) : threads;
    std::vector<double> novelties;
    while (!run_complete(s)) {
      const IterationReport report = run_iteration(s, evaluator);
      for (const auto& created : testing::events_named(report, "pair_created"))
        novelties.push_back(created["novelty"].get<double>());
    }
    ASSERT_GE(s.pairs.size(), 3u);
    // PATA-EC was at work: some child differed from the archive in how the agents ranked on it
    ASSERT_TRUE(std::any_of(novelties.begin(), novelties.end(), [](double n) { return n > 0; }));
    const uint64_t digest = fnv1a(encode_checkpoint_file(to_checkpoint(c, s)));
    EXPECT_EQ(digest, kPataEcCheckpointDigest)
        << (cached ? "behind the score cache: " : "")
        << changed("PATA-EC novelty, the ES or the POET loop (or the simulation under it)", digest,
                   kPataEcCheckpointDigest)
        << "pairs " << s.pairs.size() << ", rollouts " << s.counters.rollouts << ", env steps " << s.counters.env_steps;
    if (cached) {
      EXPECT_GT(cache.episodes_saved(), 0);
      std::printf("PATA-EC: the score cache answered %lld of %lld rollouts (%lld of %lld environment steps)\n",
                  static_cast<long long>(cache.episodes_saved()), static_cast<long long>(s.counters.rollouts),
                  static_cast<long long>(cache.steps_saved()), static_cast<long long>(s.counters.env_steps));
    }
  }
}

}  // namespace
}  // namespace poet
