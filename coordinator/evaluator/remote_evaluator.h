#pragma once
// An Evaluator whose rollouts run in poet-worker processes, on this machine or others: a ZeroMQ ROUTER socket
// that workers connect to, and the Dispatcher's queue, leases and liveness behind it. One thread owns the socket
// and answers workers at all times (also between batches, while the engine computes); evaluate() hands it a
// batch and waits. Results come back in task order, so a run gives the same numbers as with the LocalEvaluator,
// whatever the number of workers, their speed, their joining and leaving.

#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <stop_token>
#include <string>
#include <thread>

#include "dispatch/dispatcher.h"
#include "evaluator/evaluator.h"
#include "expected.h"

namespace zmq {
class context_t;
class socket_t;
}  // namespace zmq

namespace poet {

class RemoteEvaluator final : public Evaluator {
 public:
  // Binds endpoint ("tcp://0.0.0.0:5555"; "tcp://127.0.0.1:*" picks a free port) and starts the socket thread.
  // A stop request on `stop` abandons a batch in flight (EvaluationStopped).
  static Expected<std::unique_ptr<RemoteEvaluator>> bind(const std::string& endpoint, DispatchSettings settings,
                                                         std::stop_token stop);
  ~RemoteEvaluator() override;

  // Blocks until every task has a result (waiting for workers as long as it takes, and saying so in the log).
  // Throws EvaluationStopped on a stop request, and std::runtime_error naming the task when a task killed
  // settings.max_attempts workers or a worker refused it.
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks) override;

  // The endpoint bound, with its port ("tcp://127.0.0.1:41235").
  const std::string& endpoint() const { return endpoint_; }
  // Tells every connected worker the run is over (they exit), then lets the socket go.
  void shutdown_workers(const std::string& reason);
  // Called on the socket thread about twice a second, with the dispatcher under the lock (for the status board).
  void on_snapshot(std::function<void(const Dispatcher&)> publish);

 private:
  RemoteEvaluator(DispatchSettings settings, std::stop_token stop);
  void loop();
  void receive_all(Millis now);
  void handle(const std::string& peer, const std::string& payload, Millis now);
  void send(const Outgoing& message);
  void note_drop(const std::string& reason, const std::string& peer);

  std::unique_ptr<zmq::context_t> context_;
  std::unique_ptr<zmq::socket_t> socket_;
  std::string endpoint_;
  std::stop_token stop_;

  std::mutex mutex_;
  std::condition_variable changed_;
  Dispatcher dispatcher_;
  std::function<void(const Dispatcher&)> publish_;
  bool quit_ = false;
  std::string shutdown_reason_;
  bool shutdown_requested_ = false;
  std::map<std::string, Millis> last_drop_log_;  // by reason: logs at most once a second each
  std::thread thread_;
};

}  // namespace poet
