// Tests coordinator/dispatch/job_encoder.cpp: a batch's θs found by hash, each sent to a worker once per batch, and
// a Job's frame that parses as the whole Job.
#include "coordinator/dispatch/job_encoder.h"

#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <vector>

#include "common/formats/rollout_task_proto.h"
#include "simulation/envgen/named_courses.h"

namespace poet {
namespace {

std::vector<RolloutTask> two_thetas(size_t each) {
  auto a = std::make_shared<const std::vector<double>>(std::vector<double>(8, 0.5));
  auto b = std::make_shared<const std::vector<double>>(std::vector<double>(8, -0.25));
  std::vector<RolloutTask> tasks;
  for (size_t i = 0; i < 2 * each; ++i) {
    RolloutTask t;
    t.theta = i < each ? a : b;
    t.env = EnvDef{named_course("flat").value(), static_cast<uint32_t>(i)};
    t.perturbation = Perturbation{100 + i, i % 2 ? -1 : 1, 0.1};
    tasks.push_back(t);
  }
  return tasks;
}

wire::Job parsed(const Outgoing& out) {
  wire::CoordinatorMessage message;
  EXPECT_TRUE(message.ParseFromString(out.frame()));
  return message.job();
}

TEST(JobEncoder, EachThetaGoesToAWorkerOnceAndTheFrameIsTheWholeJob) {
  const std::vector<RolloutTask> tasks = two_thetas(3);
  JobEncoder encoder;
  encoder.start_batch(tasks, 7);
  EXPECT_EQ(encoder.theta_hash_of(0), theta_hash(*tasks[0].theta));
  EXPECT_EQ(encoder.theta_hash_of(5), theta_hash(*tasks[5].theta));
  std::set<uint64_t> sent_to_a;
  const wire::Job first = parsed(encoder.job("a", 1, 0, 4, sent_to_a));  // both θs
  EXPECT_EQ(first.job_id(), 1u);
  EXPECT_EQ(first.batch_id(), 7u);
  ASSERT_EQ(first.tasks_size(), 4);
  ASSERT_EQ(first.thetas_size(), 2);
  EXPECT_EQ(first.thetas(0).hash(), encoder.theta_hash_of(0));
  EXPECT_EQ(first.thetas(1).values(3), -0.25);
  EXPECT_EQ(first.tasks(3).theta_hash(), encoder.theta_hash_of(3));
  EXPECT_EQ(sent_to_a.size(), 2u);
  EXPECT_EQ(parsed(encoder.job("a", 2, 4, 6, sent_to_a)).thetas_size(), 0);  // a holds them now
  std::set<uint64_t> sent_to_b;
  EXPECT_EQ(parsed(encoder.job("b", 3, 4, 6, sent_to_b)).thetas_size(), 1);
  encoder.start_batch(tasks, 8);  // a new batch: the worker's set is the dispatcher's to clear
  std::set<uint64_t> fresh;
  EXPECT_EQ(parsed(encoder.job("a", 4, 0, 1, fresh)).batch_id(), 8u);
}

}  // namespace
}  // namespace poet
