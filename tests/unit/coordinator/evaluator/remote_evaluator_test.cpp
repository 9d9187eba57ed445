// Tests coordinator/evaluator/remote_evaluator.cpp: a tcp:// port out of range is refused before anything binds;
// results are withdrawn only with verification; a stop wakes a waiting batch at once; and `ready` runs on the
// thread that called evaluate(), with the evaluator's lock free, while an in-process worker answers.

#include "coordinator/evaluator/remote_evaluator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <future>
#include <string>
#include <thread>

#include "common/program/build_fingerprint.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "worker/job_runner.h"
#include "worker/worker_loop.h"

namespace poet {
namespace {

DispatchSettings quick_settings() {
  DispatchSettings settings;
  settings.heartbeat_ms = 100;
  settings.liveness_ms = 2000;
  settings.build = {build_fingerprint_digest(), arithmetic_digest(), arithmetic_text()};
  settings.local_token = "remote-evaluator-test";  // the test's worker is local: proven at once, never checked
  return settings;
}

std::unique_ptr<RemoteEvaluator> bound(DispatchSettings settings, std::stop_token stop = {}) {
  Expected<std::unique_ptr<RemoteEvaluator>> remote = RemoteEvaluator::bind("tcp://127.0.0.1:*", settings, stop);
  if (!remote) ADD_FAILURE() << remote.error();
  return remote ? std::move(*remote) : nullptr;
}

// A worker of this process on the evaluator's socket, as poet-worker runs one, until destroyed.
class InProcessWorker {
 public:
  explicit InProcessWorker(const std::string& endpoint) {
    worker::LoopSettings settings;
    settings.endpoint = endpoint;
    settings.session.name = "in-process";
    settings.session.local_token = quick_settings().local_token;
    thread_ = std::thread([this, settings] { worker::run_worker(settings, jobs_, wake_, stop_); });
  }
  ~InProcessWorker() {
    stop_ = true;
    wake_.notify();
    thread_.join();
  }

 private:
  WakePipe wake_;
  std::atomic<bool> stop_{false};
  worker::JobRunner jobs_{1, [this] { wake_.notify(); }};
  std::thread thread_;
};

std::vector<RolloutTask> tasks(size_t count) {
  RandomStream init(stream_key(5, "init"));
  auto theta = std::make_shared<const std::vector<double>>(random_params(init, 0.1));
  std::vector<RolloutTask> out(count);
  for (size_t i = 0; i < count; ++i) {
    out[i].theta = theta;
    out[i].env = EnvDef{*named_course("flat"), static_cast<uint32_t>(i)};
    out[i].max_steps = 20;
  }
  return out;
}

TEST(RemoteEvaluator, BindRefusesAPortOutOfRange) {
  const auto bound = RemoteEvaluator::bind("tcp://127.0.0.1:99999", DispatchSettings{}, std::stop_token{});
  ASSERT_FALSE(bound);
  EXPECT_NE(bound.error().find("1 to 65535"), std::string::npos) << bound.error();
}

TEST(RemoteEvaluator, ResultsMayBeWithdrawnOnlyWithVerification) {
  DispatchSettings settings = quick_settings();
  const std::unique_ptr<RemoteEvaluator> plain = bound(settings);
  ASSERT_TRUE(plain);
  EXPECT_FALSE(plain->withdrawals().possible);

  settings.verify_fraction = 0.05;
  const std::unique_ptr<RemoteEvaluator> verified = bound(settings);
  ASSERT_TRUE(verified);
  const Withdrawals before = verified->withdrawals();
  EXPECT_TRUE(before.possible);
  EXPECT_EQ(before.last_batch, 0u);
  EXPECT_EQ(before.withdrawn_from, std::nullopt);
  EXPECT_TRUE(before.reachable.empty());
  verified->went_back(0);  // nothing to forget
  EXPECT_EQ(verified->withdrawals().withdrawn_from, std::nullopt);
}

TEST(RemoteEvaluator, AStopWakesABatchWaitingForWorkersAtOnce) {
  std::stop_source stop;
  const std::unique_ptr<RemoteEvaluator> remote = bound(quick_settings(), stop.get_token());
  ASSERT_TRUE(remote);
  const std::vector<RolloutTask> batch = tasks(1);
  auto waited = std::async(std::launch::async, [&] { remote->evaluate(batch); });
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // no worker: the batch waits
  const auto asked = std::chrono::steady_clock::now();
  stop.request_stop();
  ASSERT_EQ(waited.wait_for(std::chrono::seconds(5)), std::future_status::ready);
  EXPECT_LT(std::chrono::steady_clock::now() - asked, std::chrono::seconds(1));
  EXPECT_THROW(waited.get(), EvaluationStopped);
}

TEST(RemoteEvaluator, ReadyRunsOnTheCallersThreadWithTheLockFree) {
  const std::unique_ptr<RemoteEvaluator> remote = bound(quick_settings());
  ASSERT_TRUE(remote);
  InProcessWorker worker(remote->endpoint());
  const std::vector<RolloutTask> batch = tasks(8);
  const std::thread::id caller = std::this_thread::get_id();
  std::vector<int> told(batch.size(), 0);
  bool on_caller = true;
  const std::vector<RolloutResult> results =
      remote->evaluate(batch, [&](size_t first, std::span<const RolloutResult> ready) {
        on_caller = on_caller && std::this_thread::get_id() == caller;
        remote->withdrawals();  // takes the evaluator's lock: under it, this would never return
        for (size_t k = 0; k < ready.size(); ++k) told.at(first + k) += 1;
      });
  ASSERT_EQ(results.size(), batch.size());
  EXPECT_TRUE(on_caller);
  for (size_t i = 0; i < batch.size(); ++i) {
    EXPECT_LE(told[i], 1) << i;
    EXPECT_EQ(results[i].total_reward, run_task(batch[i]).total_reward) << i;
  }
  EXPECT_GT(std::count(told.begin(), told.end(), 1), 0);  // a local worker's results are final as they come
  remote->shutdown_workers("test done");
}

}  // namespace
}  // namespace poet
