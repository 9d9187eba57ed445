#include "coordinator/evaluator/remote_evaluator.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <utility>
#include <zmq.hpp>

#include "common/plumbing/zmq_endpoint.h"
#include "common/text/text_format.h"
#include "coordinator/evaluator/curve_authenticator.h"
#include "simulation/rollout_task.h"

namespace poet {
namespace {

// A worker's messages are small (a Result of a job of 64 tasks is under 2 KB); anything near this is hostile.
constexpr size_t kMaxWorkerMessageBytes = 1 << 20;
// How long closing the socket may wait to deliver what was sent last.
constexpr int kFinalLingerMs = 500;
// Messages sent between yields of the socket thread (see loop()).
constexpr size_t kYieldEvery = 32;
// libzmq drops the connection of a peer that sends more than this in one frame, before the coordinator sees it
// (uncounted); frames between kMaxWorkerMessageBytes and this are read, counted as oversized and dropped.
constexpr int64_t kMaxFrameBytes = 16 << 20;

Millis now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Waits up to 10 ms for a message on the wake pipe, the job socket or the authenticator's socket (with CURVE).
void wait_for_messages(WakePipe& wake, zmq::socket_t& socket, CurveAuthenticator* authenticator) {
  zmq::pollitem_t items[] = {{nullptr, wake.read_fd(), ZMQ_POLLIN, 0},
                             {socket.handle(), 0, ZMQ_POLLIN, 0},
                             {authenticator ? authenticator->socket().handle() : nullptr, 0, ZMQ_POLLIN, 0}};
  try {
    zmq::poll(items, authenticator ? 3 : 2, std::chrono::milliseconds(10));
  } catch (const zmq::error_t& e) {
    if (e.num() != EINTR) spdlog::error("poll: {}", e.what());
  }
  wake.drain();
}

}  // namespace

RemoteEvaluator::RemoteEvaluator(DispatchSettings settings, std::stop_token stop)
    : stop_(std::move(stop)), dispatcher_(settings) {}

Expected<std::unique_ptr<RemoteEvaluator>> RemoteEvaluator::bind(const std::string& endpoint, DispatchSettings settings,
                                                                 std::stop_token stop,
                                                                 std::optional<CurveServer> curve) {
  if (std::optional<std::string> problem = zmq_endpoint_problem(endpoint, EndpointUse::kBind))
    return Unexpected{"cannot listen on " + endpoint + ": " + *problem};
  std::unique_ptr<RemoteEvaluator> evaluator(new RemoteEvaluator(settings, std::move(stop)));
  try {
    evaluator->context_ = std::make_unique<zmq::context_t>(1);
    if (curve)
      evaluator->authenticator_ = std::make_unique<CurveAuthenticator>(
          *evaluator->context_, curve->key_dir, curve->skipped_key_file, curve->refused_keys_file);
    evaluator->socket_ = std::make_unique<zmq::socket_t>(*evaluator->context_, zmq::socket_type::router);
    zmq::socket_t& socket = *evaluator->socket_;
    if (curve) {
      socket.set(zmq::sockopt::curve_server, 1);
      socket.set(zmq::sockopt::curve_secretkey, curve->secret_key);
      socket.set(zmq::sockopt::zap_domain, "poet");
    }
    socket.set(zmq::sockopt::linger, 0);
    socket.set(zmq::sockopt::router_mandatory, 1);  // a send to a vanished peer fails instead of vanishing
    socket.set(zmq::sockopt::maxmsgsize, kMaxFrameBytes);
    socket.set(zmq::sockopt::sndhwm, 10'000);
    socket.bind(endpoint);
    evaluator->endpoint_ = socket.get(zmq::sockopt::last_endpoint);
  } catch (const zmq::error_t& e) {
    return Unexpected{"cannot listen on " + endpoint + ": " + e.what()};
  }
  evaluator->thread_ = std::thread([raw = evaluator.get()] { raw->loop(); });
  return evaluator;
}

RemoteEvaluator::~RemoteEvaluator() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify();
  checks_changed_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (checker_.joinable()) checker_.join();
}

void RemoteEvaluator::check_loop() {
  std::unique_lock lock(mutex_);
  while (true) {
    checks_changed_.wait(lock, [&] { return quit_ || !checks_.empty(); });
    if (quit_) return;
    const Dispatcher::CoordinatorCheck check = std::move(checks_.front());
    checks_.pop_front();
    if (!dispatcher_.awaits_coordinator(check.batch_id, check.job_id)) continue;  // abandoned, or settled since
    lock.unlock();
    std::vector<RolloutResult> results;
    results.reserve(check.tasks.size());
    for (const RolloutTask& task : check.tasks) {
      results.push_back(run_task(task, stop_));
      if (results.back().stopped) break;  // the run stops: the batch is abandoned
    }
    lock.lock();
    if (!results.empty() && results.back().stopped) continue;
    dispatcher_.settle_by_coordinator(check.batch_id, check.job_id, results);
    wake_.notify();
  }
}

Withdrawals RemoteEvaluator::withdrawals() {
  std::lock_guard lock(mutex_);
  // a rollback asked for stands, and stays reachable, until the caller goes back
  const Referee& referee = dispatcher_.referee();
  return {dispatcher_.settings().verify_fraction > 0, dispatcher_.batch_id(), referee.rollback_asked(),
          referee.unchecked_since()};
}

void RemoteEvaluator::went_back(uint64_t last_batch) {
  std::lock_guard lock(mutex_);
  dispatcher_.went_back(last_batch);
}

void RemoteEvaluator::on_snapshot(std::function<void(DispatchView)> publish) {
  std::lock_guard lock(mutex_);
  publish_ = std::move(publish);
}

void RemoteEvaluator::log_summary() {
  std::lock_guard lock(mutex_);
  const DispatchView d = dispatcher_.view(now_ms());
  if (dispatcher_.settings().verify_fraction > 0)
    spdlog::info(
        "verification: {} answers checked ({} by the coordinator itself), {} worker(s) refused for wrong results, "
        "{} time(s) gone back to a checkpoint",
        d.verified_jobs, d.coordinator_checks, d.wrong_workers, d.rollbacks);
  if (d.workers_demoted > 0 || d.leases_expired > 0)
    spdlog::info("{} worker(s) demoted, {} lease(s) expired on workers that had returned no result",
                 d.workers_demoted, d.leases_expired);
}

void RemoteEvaluator::shutdown_workers(const std::string& reason) {
  std::unique_lock lock(mutex_);
  shutdown_requested_ = true;
  shutdown_reason_ = reason;
  wake_.notify();
  // The socket thread tells the known workers at once; then every peer that speaks within one heartbeat interval
  // (every live worker does) is told too, also one the dispatcher had dropped as silent a moment ago.
  const auto window = std::chrono::milliseconds(std::min<Millis>(dispatcher_.settings().heartbeat_ms + 100, 2000));
  changed_.wait_for(lock, window, [this] { return quit_; });
}

std::vector<RolloutResult> RemoteEvaluator::evaluate(std::span<const RolloutTask> tasks, const ResultsReady& ready) {
  // Registered before the lock is taken, as it runs at once when the stop came first; destroyed after the lock is
  // released, as its destructor waits for a run on another thread that may be waiting for the lock.
  const std::stop_callback wake_on_stop(stop_, [this] {
    { std::lock_guard lock(mutex_); }  // a waiter is either not yet waiting (it sees the stop) or is woken
    changed_.notify_all();
  });
  std::unique_lock lock(mutex_);
  dispatcher_.start_batch(tasks);
  wake_.notify();
  collect_ready_ = static_cast<bool>(ready);
  struct StopCollecting {  // however evaluate() ends (with the lock held), nothing more is collected for it
    RemoteEvaluator& self;
    ~StopCollecting() {
      self.collect_ready_ = false;
      self.ready_results_.clear();
    }
  } stop_collecting{*this};
  changed_.notify_all();
  Millis waiting_since = now_ms();
  bool said_waiting = false;
  for (;;) {
    // woken by the socket thread or a stop; otherwise when it is time to say the run waits for workers
    const Millis patience = said_waiting ? 60'000 : 2'000;
    changed_.wait_for(lock, std::chrono::milliseconds(std::max<Millis>(0, waiting_since + patience - now_ms())), [&] {
      return stop_.stop_requested() || !ready_results_.empty() || dispatcher_.failure() || dispatcher_.batch_done();
    });
    if (stop_.stop_requested()) {
      dispatcher_.abandon_batch();
      throw EvaluationStopped();
    }
    if (const auto& failure = dispatcher_.failure()) {
      const std::string message = *failure;
      dispatcher_.abandon_batch();
      throw std::runtime_error(message);
    }
    if (!ready_results_.empty()) {
      tell_ready(lock, ready);
      continue;
    }
    if (dispatcher_.batch_done()) return dispatcher_.take_results();
    // say so when the run waits for workers, then every minute while it still does
    if (dispatcher_.ready_workers() > 0) {
      waiting_since = now_ms();
      said_waiting = false;
    } else if (now_ms() - waiting_since >= patience) {
      spdlog::warn("waiting for workers: none is connected to {} ({} jobs queued)", endpoint_,
                   dispatcher_.view(now_ms()).queue_depth);
      waiting_since = now_ms();
      said_waiting = true;
    }
  }
}

void RemoteEvaluator::tell_ready(std::unique_lock<std::mutex>& lock, const ResultsReady& ready) {
  const std::vector<Dispatcher::Ready> told = std::exchange(ready_results_, {});
  lock.unlock();
  try {
    for (const Dispatcher::Ready& range : told) ready(range.first, range.results);
  } catch (...) {
    lock.lock();
    dispatcher_.abandon_batch();
    throw;
  }
  lock.lock();
}

void RemoteEvaluator::loop() {
  Millis last_publish = 0;
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (quit_) {
        // the last messages (the Shutdowns) get a moment to leave; linger 0 would discard them at close
        socket_->set(zmq::sockopt::linger, kFinalLingerMs);
        return;
      }
    }
    wait_for_messages(wake_, *socket_, authenticator_.get());
    const Millis now = now_ms();
    std::lock_guard lock(mutex_);
    serve(now);
    if (publish_ && now - last_publish >= 500) {
      publish_(dispatcher_.view(now));
      last_publish = now;
    }
  }
}

void RemoteEvaluator::serve(Millis now) {
  if (authenticator_) {
    authenticator_->answer_all([&](const std::string& key, const std::string& reason) {
      note_drop(DropReason::kUnauthorisedKey, "a worker with CURVE key " + key + " (" + reason + ")");
    });
  }
  const int64_t demoted_before = dispatcher_.referee().counts().demoted;
  receive_all(now);
  for (Dispatcher::Ready& ready : dispatcher_.take_ready())
    if (collect_ready_) ready_results_.push_back(std::move(ready));  // (else nobody listens)
  for (const WorkerId& dead : dispatcher_.expire(now)) {
    if (const auto held_back = log_lost_.admit(now))
      spdlog::warn("worker {} silent for {} ms: removed, its jobs go back to the queue{}", peer_id_text(dead),
                   dispatcher_.settings().liveness_ms, LogThrottle::held_back_note(*held_back));
  }
  if (shutdown_requested_) send_shutdowns();
  const int64_t backups_before = dispatcher_.backup_jobs();
  refuse_keys();
  send_outgoing(now);
  if (const int64_t demoted = dispatcher_.referee().counts().demoted - demoted_before; demoted > 0) {
    if (const auto held_back = log_demoted_.admit(now))
      spdlog::warn(
          "{} worker(s) that never returned a result let a lease expire or returned an error: given "
          "no more jobs ({} so far){}",
          demoted, dispatcher_.referee().counts().demoted, LogThrottle::held_back_note(*held_back));
  }
  start_coordinator_checks();
  // from every path: this thread's answers and the checker's (check_loop)
  for (size_t& i = wrong_logged_; i < dispatcher_.referee().refusals().size(); ++i)
    spdlog::error("worker {} {}: refused, and its results of this batch are computed again",
                  dispatcher_.referee().refusals()[i].name, dispatcher_.referee().refusals()[i].why);
  if (const int64_t backups = dispatcher_.backup_jobs() - backups_before; backups > 0) {
    if (const auto held_back = log_backups_.admit(now))
      spdlog::warn("{} job(s) held far longer than this batch's jobs take: sent to a second worker too{}", backups,
                   LogThrottle::held_back_note(*held_back));
  }
  if (!ready_results_.empty() || dispatcher_.batch_done() || dispatcher_.failure()) changed_.notify_all();
}

void RemoteEvaluator::send_shutdowns() {
  for (const WorkerView& w : dispatcher_.workers()) {
    Outgoing bye{w.id, {}};
    bye.message.mutable_shutdown()->set_reason(shutdown_reason_);
    send(bye);
  }
  shutdown_requested_ = false;
  shutting_down_ = true;
}

// A worker found wrong (by an answer or the checker): its key refused before it is told, so that it cannot come back
// on a new socket (the dispatcher has refused every connection holding it already).
void RemoteEvaluator::refuse_keys() {
  for (const std::string& key : dispatcher_.take_refused_keys())
    if (authenticator_) authenticator_->refuse(key);
}

void RemoteEvaluator::send_outgoing(Millis now) {
  std::vector<WorkerId> unreachable;  // told to the dispatcher once it has made every message
  size_t sent = 0;
  dispatcher_.outgoing(now, [&](Outgoing&& message) {
    if (!transmit(message)) unreachable.push_back(message.worker);
    // Making a batch's first jobs takes milliseconds; ZeroMQ's I/O thread, when it shares this thread's core,
    // would otherwise ship none of them until all are made, and the workers wait.
    if (++sent % kYieldEvery == 0) std::this_thread::yield();
  });
  for (const WorkerId& id : unreachable) dispatcher_.lose_worker(id);
}

void RemoteEvaluator::start_coordinator_checks() {
  for (Dispatcher::CoordinatorCheck& check : dispatcher_.take_coordinator_checks()) {
    if (check.disputed)
      spdlog::warn(
          "workers answered job {} differently and no other witness can decide: the coordinator runs its {} "
          "task(s) itself",
          check.job_id, check.tasks.size());
    else
      spdlog::debug("no other worker can check job {}: the coordinator runs its {} task(s) itself", check.job_id,
                    check.tasks.size());
    checks_.push_back(std::move(check));
    if (!checker_.joinable()) checker_ = std::thread([this] { check_loop(); });
    checks_changed_.notify_one();
  }
}

void RemoteEvaluator::receive_all(Millis now) {
  for (int budget = 0; budget < 10'000; ++budget) {
    zmq::message_t peer;
    if (!socket_->recv(peer, zmq::recv_flags::dontwait)) return;
    std::vector<zmq::message_t> frames;
    while (true) {  // a ROUTER always delivers the whole message once its first frame is here
      int more = socket_->get(zmq::sockopt::rcvmore);
      if (!more) break;
      zmq::message_t frame;
      if (!socket_->recv(frame, zmq::recv_flags::dontwait)) break;
      frames.push_back(std::move(frame));
    }
    const std::string id = peer.to_string();
    if (frames.size() != 1) {
      note_drop(DropReason::kMalformed, "peer " + peer_id_text(id));
      continue;
    }
    if (frames[0].size() > kMaxWorkerMessageBytes) {
      note_drop(DropReason::kOversized, "peer " + peer_id_text(id));
      continue;
    }
    handle(id, frames[0], now);
  }
}

std::string RemoteEvaluator::key_of(zmq::message_t& frame) const {
  if (!authenticator_) return {};
  try {
    // the key the ZAP handler admitted this connection with: a routing id freed by one connection may be taken by
    // another, of another key, so it is read from the Hello itself
    return frame.gets("User-Id");
  } catch (const zmq::error_t&) {
    return {};
  }
}

void RemoteEvaluator::handle(const std::string& peer, zmq::message_t& payload, Millis now) {
  wire::WorkerMessage message;
  if (!message.ParseFromArray(payload.data(), static_cast<int>(payload.size())) ||
      message.kind_case() == wire::WorkerMessage::KIND_NOT_SET) {
    note_drop(DropReason::kMalformed, "peer " + peer_id_text(peer));
    return;
  }
  if (shutting_down_) {  // whoever it is: the run is over
    if (message.has_goodbye()) return;
    Outgoing bye{peer, {}};
    bye.message.mutable_shutdown()->set_reason(shutdown_reason_);
    send(bye);
    return;
  }
  switch (message.kind_case()) {
    case wire::WorkerMessage::kHello: {
      // with CURVE: the connection's key is its witness
      Outgoing reply{peer, dispatcher_.on_hello(peer, message.hello(), now, key_of(payload))};
      const std::string name = message.hello().name().substr(0, 200);
      if (reply.message.has_refused()) {  // counted by the dispatcher
        if (const auto held_back = log_refused_.admit(now))
          spdlog::warn("refused worker {}: {}{}", name, reply.message.refused().reason(),
                       LogThrottle::held_back_note(*held_back));
      } else if (const auto held_back = log_joined_.admit(now)) {
        spdlog::info("worker {} ({} threads) joined: {} connected{}", name, message.hello().threads(),
                     dispatcher_.worker_count(), LogThrottle::held_back_note(*held_back));
      }
      send(reply);
      return;
    }
    case wire::WorkerMessage::kResult:
    case wire::WorkerMessage::kHeartbeat:
      if (!dispatcher_.heard_from(peer, now)) {
        // a worker of an earlier coordinator on this port, or one counted dead: it must start afresh
        note_drop(DropReason::kUnknownPeer, "peer " + peer_id_text(peer));
        Outgoing rejoin{peer, {}};
        rejoin.message.mutable_rejoin()->set_reason("this coordinator does not know the worker: say Hello again");
        send(rejoin);
        return;
      }
      if (message.has_result()) dispatcher_.on_result(peer, message.result(), now);
      return;
    case wire::WorkerMessage::kGoodbye:
      if (!dispatcher_.heard_from(peer, now)) return;
      dispatcher_.remove_worker(peer, /*died=*/false);
      if (const auto held_back = log_left_.admit(now))
        spdlog::info("worker {} left: {} connected{}", peer_id_text(peer), dispatcher_.worker_count(),
                     LogThrottle::held_back_note(*held_back));
      return;
    default:
      note_drop(DropReason::kMalformed, "peer " + peer_id_text(peer));
  }
}

void RemoteEvaluator::send(const Outgoing& message) {
  if (!transmit(message)) dispatcher_.lose_worker(message.worker);  // a no-op for a peer it does not know
}

bool RemoteEvaluator::transmit(const Outgoing& message) {
  try {
    zmq::message_t id(message.worker.data(), message.worker.size());
    zmq::message_t payload(message.frame_size());  // written in place: a Job's θs are copied once, here
    message.write_frame(static_cast<char*>(payload.data()));
    // false: its queue is full, it is not keeping up
    return socket_->send(id, zmq::send_flags::sndmore | zmq::send_flags::dontwait) &&
           socket_->send(payload, zmq::send_flags::dontwait);
  } catch (const zmq::error_t& e) {
    // EHOSTUNREACH: the peer's connection is gone (a killed worker, or libzmq cut it for a frame over
    // maxmsgsize); its jobs go back to the queue
    spdlog::debug("send to {}: {}", peer_id_text(message.worker), e.what());
    return false;
  }
}

void RemoteEvaluator::note_drop(DropReason reason, const std::string& who) {
  const int64_t so_far = dispatcher_.count_drop(reason);
  const auto held_back = log_drops_[reason].admit(now_ms());
  if (!held_back) return;
  spdlog::warn("refused {}: {} ({} so far){}", who, name(reason), so_far, LogThrottle::held_back_note(*held_back));
}

}  // namespace poet
