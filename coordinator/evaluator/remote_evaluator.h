#pragma once
// An Evaluator whose rollouts run in poet-worker processes, on this machine or others: a ZeroMQ ROUTER socket
// that workers connect to, and the Dispatcher's queue, leases and liveness behind it. One thread owns the socket
// and answers workers at all times (also between batches, while the engine computes); evaluate() hands it a
// batch and waits. Results come back in task order, so a run gives the same numbers as with the LocalEvaluator,
// whatever the number of workers, their speed, their joining and leaving.

#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include "common/plumbing/expected.h"
#include "common/plumbing/wake_pipe.h"
#include "coordinator/dispatch/dispatcher.h"
#include "coordinator/evaluator/log_throttle.h"
#include "engine/evaluator.h"

namespace zmq {
class context_t;
class message_t;
class socket_t;
}  // namespace zmq

namespace poet {

class CurveAuthenticator;

// CURVE on the job socket: the coordinator's secret key, and the key directory whose authorized/*.key are the
// workers it accepts (common/plumbing/curve_keys.h).
struct CurveServer {
  std::string secret_key;  // Z85
  std::filesystem::path key_dir;
  std::function<void()> skipped_key_file;  // told of each file of authorized/ that holds no key (curve_authenticator.h)
  std::filesystem::path refused_keys_file;  // the keys of workers refused for wrong results, kept across a resume
};

class RemoteEvaluator final : public Evaluator {
 public:
  // Binds endpoint ("tcp://0.0.0.0:5555"; "tcp://127.0.0.1:*" picks a free port; common/plumbing/zmq_endpoint.h says
  // which are refused before ZeroMQ sees them) and starts the socket thread. A stop request on `stop` abandons a batch
  // in flight (EvaluationStopped). With `curve`, only workers holding an authorised key can connect.
  static Expected<std::unique_ptr<RemoteEvaluator>> bind(const std::string& endpoint, DispatchSettings settings,
                                                         std::stop_token stop,
                                                         std::optional<CurveServer> curve = std::nullopt);
  ~RemoteEvaluator() override;

  // Blocks until every task has a result (waiting for workers as long as it takes, and saying so in the log).
  // Throws EvaluationStopped on a stop request, and std::runtime_error naming the task when a task killed
  // settings.max_attempts workers or a worker refused it.
  // Waits on a condition the socket thread (and a stop request) notifies; `ready` hears of each job's results as
  // they become final, on this thread with the lock released, so the socket thread keeps serving meanwhile.
  std::vector<RolloutResult> evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) override;
  using Evaluator::evaluate;
  // With verification (trust's rollback record): the batches whose final results a worker found
  // wrong later may have lied in.
  Withdrawals withdrawals() override;
  void went_back(uint64_t last_batch) override;

  // The endpoint bound, with its port ("tcp://127.0.0.1:41235").
  const std::string& endpoint() const { return endpoint_; }
  // Tells every connected worker the run is over (they exit): the known ones at once, then any peer that speaks
  // within the next heartbeat interval. Returns after that interval (at most about two seconds).
  void shutdown_workers(const std::string& reason);
  // Logs what the run's workers cost and did beyond their jobs: checks, demotions, refusals, going back.
  void log_summary();
  // Called on the socket thread about twice a second with the dispatcher's view of itself (for the status board).
  void on_snapshot(std::function<void(DispatchView)> publish);

 private:
  RemoteEvaluator(DispatchSettings settings, std::stop_token stop);
  // Tells `ready` of the results collected so far, with the lock released; on a throw the batch is abandoned.
  void tell_ready(std::unique_lock<std::mutex>& lock, const ResultsReady& ready);
  void loop();
  // One round of the socket thread, under the lock: the messages in, the final results collected, workers lost,
  // Shutdowns, refused keys, the messages out, the coordinator's checks, and the log of what changed.
  void serve(Millis now);
  void send_shutdowns();                // to every known worker, once shutdown_workers() asks
  void refuse_keys();                   // with CURVE: the keys of the workers found wrong, at the handshake
  void send_outgoing(Millis now);       // what the dispatcher has to send; workers that cannot be reached are lost
  void start_coordinator_checks();      // hands the checks only the coordinator can run to check_loop()
  void receive_all(Millis now);
  void handle(const std::string& peer, zmq::message_t& payload, Millis now);
  std::string key_of(zmq::message_t& frame) const;            // with CURVE: the key its connection was admitted with
  void send(const Outgoing& message);                         // and a worker it cannot reach is lost
  bool transmit(const Outgoing& message);                     // false: the worker cannot be reached
  void note_drop(DropReason reason, const std::string& who);  // counts, and logs at most once a second
  // The coordinator's own runs of jobs no worker can check (Dispatcher::take_coordinator_checks), one at a time on
  // a thread of their own, so that the socket thread keeps answering.
  void check_loop();

  std::unique_ptr<zmq::context_t> context_;
  std::unique_ptr<CurveAuthenticator> authenticator_;  // with CURVE only
  std::unique_ptr<zmq::socket_t> socket_;
  WakePipe wake_;  // a new batch, a shutdown or quit: the socket thread acts at once, not at its next poll timeout
  std::string endpoint_;
  std::stop_token stop_;

  std::mutex mutex_;
  std::condition_variable changed_;  // results collected, the batch done or failed, a stop requested, quit
  Dispatcher dispatcher_;
  std::function<void(DispatchView)> publish_;
  bool collect_ready_ = false;  // while evaluate() runs with a listener: final results are copied for it
  std::vector<Dispatcher::Ready> ready_results_;  // final results taken for evaluate()'s thread to tell
  bool quit_ = false;
  std::string shutdown_reason_;
  bool shutdown_requested_ = false;
  bool shutting_down_ = false;  // Shutdowns sent: every message is answered with another
  // the log of a flood of peers: a few lines a second of each kind
  std::map<DropReason, LogThrottle> log_drops_;  // by reason, one a second
  LogThrottle log_joined_{5};
  LogThrottle log_left_{5};
  LogThrottle log_lost_{5};
  LogThrottle log_backups_{1};
  LogThrottle log_demoted_{1};
  LogThrottle log_refused_{5};
  size_t wrong_logged_ = 0;  // workers refused for wrong results that the log has named
  std::thread thread_;
  std::deque<Dispatcher::CoordinatorCheck> checks_;  // waiting for the checker (under mutex_)
  std::condition_variable checks_changed_;
  std::thread checker_;
};

}  // namespace poet
