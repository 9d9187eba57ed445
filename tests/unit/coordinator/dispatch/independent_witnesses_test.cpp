// Tests the rules of independent witnesses (coordinator/trust/verification.h) through the Dispatcher, over many
// random schedules: honest workers and one liar that answers every job with the same wrong results, either from
// many identities (a new connection every two jobs, as without CURVE anyone may open) or from many connections on
// one CURVE key (with the honest workers sharing another key, as Compose's one worker key pair has them). Answers
// come late and in any order, identities leave with answers held, and the coordinator settles its checks late.
// Whatever the schedule: the batch ends with the honest results, no honest worker is refused, and the liar is.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "coordinator/dispatch/dispatcher.h"
#include "dispatch_fixture.h"

namespace poet {
namespace {

using namespace dispatch_fixture;

enum class Liar { kManyIdentities, kManyConnectionsOnOneKey };

struct Outcome {
  bool done = false;
  std::vector<RolloutResult> results;
  std::set<std::string> refused;       // names of the workers refused
  std::set<std::string> refused_keys;  // CURVE keys refused
  int liar_answers = 0;
  int liar_identities = 0;
};

wire::Result lie(const wire::Job& job) {
  wire::Result r = answer(job);
  for (wire::TaskResult& t : *r.mutable_results()) t.set_total_reward(t.total_reward() + 1);
  return r;
}

bool is_liar(const WorkerId& id) { return id.starts_with("liar"); }

Outcome run_schedule(Liar liar, uint64_t seed) {
  std::mt19937_64 rng(seed);
  const auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<uint64_t>(n)); };
  DispatchSettings s = settings();
  s.verify_fraction = pick(2) == 0 ? 1.0 : 0.05;
  s.verify_secret = seed;
  s.probation_checks = 1 + pick(4);
  Dispatcher d(s);
  Outcome outcome;
  const int honest = 2 + pick(3);
  const std::string honest_key = liar == Liar::kManyConnectionsOnOneKey ? "honest-key" : "";
  for (int i = 0; i < honest; ++i)
    join(d, "honest" + std::to_string(i), stranger_hello("honest" + std::to_string(i)), 0, honest_key);
  std::map<WorkerId, int> answered;  // by each liar identity
  const auto new_liar = [&](Millis now) {
    const WorkerId id = "liar" + std::to_string(outcome.liar_identities++);
    join(d, id, stranger_hello(id), now, liar == Liar::kManyConnectionsOnOneKey ? "liar-key" : "");
  };
  const int liar_connections = liar == Liar::kManyConnectionsOnOneKey ? 3 + pick(6) : 1;
  for (int i = 0; i < liar_connections; ++i) new_liar(0);

  d.start_batch(batch(24));
  struct Pending {
    Millis due;
    Outgoing job;
  };
  std::vector<Pending> pending;
  std::vector<std::pair<Millis, Dispatcher::CoordinatorCheck>> checks;
  Millis now = 1;
  for (int round = 0; round < 5000 && !d.batch_done() && !d.failure(); ++round, now += 10) {
    for (Outgoing& o : jobs_in(d.outgoing(now))) pending.push_back({now + 10 * pick(4), std::move(o)});
    std::shuffle(pending.begin(), pending.end(), rng);
    std::vector<Pending> later;
    for (Pending& p : pending) {
      const WorkerId& id = p.job.worker;
      if (p.due > now || !connected(d, id)) {
        if (connected(d, id)) later.push_back(std::move(p));
        continue;
      }
      if (!is_liar(id)) {
        d.on_result(id, answer(p.job.message.job()), now);
        continue;
      }
      d.on_result(id, lie(p.job.message.job()), now);
      outcome.liar_answers += 1;
      // without CURVE an identity costs nothing: a new one every two jobs, the old one gone with its answers held
      if (liar == Liar::kManyIdentities && ++answered[id] == 2 && connected(d, id) && outcome.liar_identities < 40) {
        d.remove_worker(id, /*died=*/false);
        new_liar(now);
      }
    }
    pending = std::move(later);
    // a refused worker's key is refused at once, with every connection holding it
    for (const std::string& key : d.take_refused_keys()) outcome.refused_keys.insert(key);
    if (!outcome.refused_keys.empty()) {
      for (int i = 0; i < liar_connections; ++i) EXPECT_FALSE(connected(d, "liar" + std::to_string(i))) << i;
    }
    for (Dispatcher::CoordinatorCheck& check : d.take_coordinator_checks())
      checks.emplace_back(now + 10 * pick(5), std::move(check));
    std::erase_if(checks, [&](const auto& due_check) {
      if (due_check.first > now) return false;
      d.settle_by_coordinator(due_check.second.batch_id, due_check.second.job_id,
                              coordinators_results(due_check.second));
      return true;
    });
    for (const WorkerView& w : d.workers()) d.heard_from(w.id, now);
  }
  EXPECT_FALSE(d.failure()) << *d.failure();
  outcome.done = d.batch_done();
  for (const Refusal& r : d.referee().refusals()) outcome.refused.insert(r.name);
  if (outcome.done) outcome.results = d.take_results();
  return outcome;
}

void expect_honest_outcome(Liar liar, uint64_t seed) {
  SCOPED_TRACE("schedule seed " + std::to_string(seed));
  const Outcome outcome = run_schedule(liar, seed);
  ASSERT_TRUE(outcome.done);
  ASSERT_EQ(outcome.results.size(), 24u);
  for (size_t i = 0; i < outcome.results.size(); ++i)
    EXPECT_EQ(outcome.results[i].total_reward, static_cast<double>(i)) << "task " << i << ": a lie was taken";
  for (const std::string& name : outcome.refused) EXPECT_TRUE(is_liar(name)) << name << " is honest, and was refused";
  if (outcome.liar_answers > 0) {
    EXPECT_FALSE(outcome.refused.empty()) << "the liar answered and was not refused";
  }
  if (liar == Liar::kManyConnectionsOnOneKey && outcome.liar_answers > 0) {
    EXPECT_EQ(outcome.refused.size(), static_cast<size_t>(outcome.liar_identities)) << "every connection of its key";
    EXPECT_EQ(outcome.refused_keys, std::set<std::string>{"liar-key"});
  }
  if (liar == Liar::kManyIdentities) {
    EXPECT_TRUE(outcome.refused_keys.empty()) << "without CURVE no key is refused";
  }
}

TEST(IndependentWitnesses, ALiarWithANewIdentityEveryTwoJobsNeverOutvotesHonestWorkers) {
  for (uint64_t seed = 1; seed <= 150; ++seed) expect_honest_outcome(Liar::kManyIdentities, seed);
}

TEST(IndependentWitnesses, ALiarWithManyConnectionsOnOneKeyNeverOutvotesHonestWorkersThatShareAKey) {
  for (uint64_t seed = 1; seed <= 150; ++seed) expect_honest_outcome(Liar::kManyConnectionsOnOneKey, seed);
}

}  // namespace
}  // namespace poet
