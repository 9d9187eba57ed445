#include "common/formats/rollout_task_proto.h"

#include <gtest/gtest.h>

#include <bit>
#include <limits>
#include <memory>

#include "simulation/envgen/cppn_mutation.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet {
namespace {

// A task on a CPPN course grown by a few mutations, as the coordinator sends it.
RolloutTask cppn_task() {
  RandomStream stream(stream_key(8, "wire-cppn"));
  CppnGenome genome = first_cppn_genome(stream);
  for (int i = 0; i < 6; ++i) genome = mutate_cppn(genome, stream);
  RolloutTask task;
  RandomStream init(stream_key(8, "init"));
  task.theta = std::make_shared<const std::vector<double>>(random_params(init));
  task.env.encoding.cppn = std::make_shared<const CppnGenome>(genome);
  task.env.encoding.name = cppn_name(genome);
  task.env.seed = 12;
  task.max_steps = 80;
  return task;
}

TEST(RolloutTaskProto, ACppnCourseTravelsExactly) {
  const RolloutTask task = cppn_task();
  const uint64_t hash = theta_hash(*task.theta);
  ThetaCache cache{{hash, task.theta}};
  const Expected<RolloutTask> back = task_from_wire(to_wire(task, hash), cache);
  ASSERT_TRUE(back) << back.error();
  EXPECT_EQ(*back->env.encoding.cppn, *task.env.encoding.cppn);
  const RolloutResult here = run_task(task), there = run_task(*back);
  EXPECT_EQ(std::bit_cast<uint64_t>(here.total_reward), std::bit_cast<uint64_t>(there.total_reward));
  EXPECT_EQ(here.steps, there.steps);
}

TEST(RolloutTaskProto, AHostileGenomeOnTheWireIsRefusedNamingTheField) {
  const RolloutTask task = cppn_task();
  const uint64_t hash = theta_hash(*task.theta);
  ThetaCache cache{{hash, task.theta}};
  wire::Task looped = to_wire(task, hash);
  pb::CppnConnection* back_edge = looped.mutable_env()->mutable_encoding()->mutable_cppn()->add_connections();
  back_edge->set_from_node(1);
  back_edge->set_to_node(1);
  back_edge->set_weight(1.0);
  const Expected<RolloutTask> loop = task_from_wire(looped, cache);
  ASSERT_FALSE(loop);
  EXPECT_TRUE(loop.error().starts_with("env.encoding.cppn.connections[")) << loop.error();
  wire::Task huge = to_wire(task, hash);
  for (int i = 0; i < 1'000'000; ++i) huge.mutable_env()->mutable_encoding()->mutable_cppn()->add_nodes();
  const Expected<RolloutTask> many = task_from_wire(huge, cache);
  ASSERT_FALSE(many);
  EXPECT_EQ(many.error(), "env.encoding.cppn.nodes: " +
                              std::to_string(1'000'000 + task.env.encoding.cppn->nodes.size()) + " nodes; at most 256");
}

TEST(RolloutTaskProto, AResultHoldsItsRolloutResultsOnlyWhenEveryOneIsThereAndValid) {
  wire::Result result;
  for (int i = 0; i < 2; ++i) {
    wire::TaskResult* one = result.add_results();
    one->set_total_reward(1.5 + i);
    one->set_steps(10);
  }
  const std::optional<std::vector<RolloutResult>> both = results_from_wire(result, 2);
  ASSERT_TRUE(both);
  EXPECT_EQ((*both)[1].total_reward, 2.5);
  EXPECT_FALSE(results_from_wire(result, 3));  // a job of three tasks: one is missing
  result.mutable_results(1)->set_total_reward(std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(results_from_wire(result, 2));
}

}  // namespace
}  // namespace poet
