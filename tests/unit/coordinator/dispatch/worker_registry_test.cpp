// Tests coordinator/dispatch/worker_registry.cpp: workers in the order they said Hello, silence, and trials.
#include "coordinator/dispatch/worker_registry.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

WorkerFacts hello(const WorkerId& id) {
  WorkerFacts facts;
  facts.id = id;
  facts.name = "worker-" + id;
  return facts;
}

// Standings as the referee keeps them, one proven.
const Standing kNew;
Standing proven() {
  Standing s;
  s.proven = true;
  return s;
}
const Standing kProven = proven();

TEST(WorkerRegistry, WorkersKeepTheOrderTheySaidHelloInWithTheirStanding) {
  WorkerRegistry registry;
  registry.add(hello("b"), kNew, 0);
  registry.add(hello("a"), kProven, 0);
  registry.add(hello("c"), kNew, 0);
  ASSERT_EQ(registry.in_order().size(), 3u);
  EXPECT_EQ(registry.in_order()[0]->facts.id, "b");
  EXPECT_EQ(registry.in_order()[1]->facts.id, "a");
  EXPECT_TRUE(registry.find("a")->standing->proven);
  EXPECT_FALSE(registry.find("b")->standing->proven);
  EXPECT_EQ(registry.proven(), 1u);
  EXPECT_EQ(registry.joined(), 3);

  const std::optional<RegisteredWorker> removed = registry.remove("a");
  ASSERT_TRUE(removed);
  EXPECT_EQ(removed->facts.name, "worker-a");
  EXPECT_FALSE(registry.remove("a"));
  EXPECT_EQ(registry.in_order()[1]->facts.id, "c");
  EXPECT_EQ(registry.find("a"), nullptr);
}

TEST(WorkerRegistry, AWorkerIsReadyOnceHeardFromAndSilentOnceNotForLonger) {
  WorkerRegistry registry;
  registry.add(hello("a"), kNew, 0);
  registry.add(hello("b"), kNew, 0);
  EXPECT_EQ(registry.ready(), 0u);  // a Hello proves nothing about listening
  EXPECT_TRUE(registry.heard_from("a", 500));
  EXPECT_FALSE(registry.heard_from("stranger", 500));
  EXPECT_EQ(registry.ready(), 1u);
  EXPECT_EQ(registry.silent(1000, 800), (std::vector<WorkerId>{"b"}));
  EXPECT_EQ(registry.silent(1400, 800), (std::vector<WorkerId>{"a", "b"}));
}

TEST(WorkerRegistry, AWorkerNotProvenIsOnTrialFromItsFirstJob) {
  WorkerRegistry registry;
  RegisteredWorker& a = registry.add(hello("a"), kNew, 0);
  registry.sent_job(a, 7, 100);
  registry.sent_job(a, 8, 150);
  EXPECT_EQ(a.trial_since, 100);
  EXPECT_EQ(a.trial_job, 7u);
  EXPECT_TRUE(registry.unproven_holding());
  EXPECT_EQ(registry.jobs_held(), 2);
  EXPECT_EQ(registry.views()[0].jobs_held, 2u);
}

}  // namespace
}  // namespace poet
