#include "evaluator/remote_evaluator.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <stdexcept>
#include <zmq.hpp>

namespace poet {
namespace {

// A worker's messages are small (a Result of a job of 64 tasks is under 2 KB); anything near this is hostile.
constexpr size_t kMaxWorkerMessageBytes = 1 << 20;
// libzmq drops the connection of a peer that sends more than this in one frame.
constexpr int64_t kMaxFrameBytes = 4 << 20;

Millis now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::string printable(const std::string& peer) {
  static const char* kHex = "0123456789abcdef";
  std::string out;
  for (unsigned char c : peer) {
    out += kHex[c >> 4];
    out += kHex[c & 15];
  }
  return out;
}

}  // namespace

RemoteEvaluator::RemoteEvaluator(DispatchSettings settings, std::stop_token stop)
    : stop_(std::move(stop)), dispatcher_(settings) {}

Expected<std::unique_ptr<RemoteEvaluator>> RemoteEvaluator::bind(const std::string& endpoint, DispatchSettings settings,
                                                                 std::stop_token stop) {
  std::unique_ptr<RemoteEvaluator> evaluator(new RemoteEvaluator(settings, std::move(stop)));
  try {
    evaluator->context_ = std::make_unique<zmq::context_t>(1);
    evaluator->socket_ = std::make_unique<zmq::socket_t>(*evaluator->context_, zmq::socket_type::router);
    zmq::socket_t& socket = *evaluator->socket_;
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
  if (thread_.joinable()) thread_.join();
}

void RemoteEvaluator::on_snapshot(std::function<void(const Dispatcher&)> publish) {
  std::lock_guard lock(mutex_);
  publish_ = std::move(publish);
}

void RemoteEvaluator::shutdown_workers(const std::string& reason) {
  {
    std::lock_guard lock(mutex_);
    shutdown_requested_ = true;
    shutdown_reason_ = reason;
  }
  // the socket thread sends the Shutdowns on its next turn; give it that turn
  for (int i = 0; i < 50; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::lock_guard lock(mutex_);
    if (!shutdown_requested_) break;
  }
}

std::vector<RolloutResult> RemoteEvaluator::evaluate(std::span<const RolloutTask> tasks) {
  std::unique_lock lock(mutex_);
  dispatcher_.start_batch(tasks);
  changed_.notify_all();
  Millis waiting_since = now_ms();
  bool said_waiting = false;
  for (;;) {
    changed_.wait_for(lock, std::chrono::milliseconds(100));
    if (stop_.stop_requested()) {
      dispatcher_.abandon_batch();
      throw EvaluationStopped();
    }
    if (const auto& failure = dispatcher_.failure()) {
      const std::string message = *failure;
      dispatcher_.abandon_batch();
      throw std::runtime_error(message);
    }
    if (dispatcher_.batch_done()) return dispatcher_.take_results();
    // say so when the run waits for workers, then every minute while it still does
    if (dispatcher_.worker_count() > 0) {
      waiting_since = now_ms();
      said_waiting = false;
    } else if (now_ms() - waiting_since > (said_waiting ? 60'000 : 2'000)) {
      spdlog::warn("waiting for workers: none is connected to {} ({} jobs queued)", endpoint_,
                   dispatcher_.queue_depth());
      waiting_since = now_ms();
      said_waiting = true;
    }
  }
}

void RemoteEvaluator::loop() {
  Millis last_publish = 0;
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (quit_) return;
    }
    zmq::pollitem_t items[] = {{socket_->handle(), 0, ZMQ_POLLIN, 0}};
    try {
      zmq::poll(items, 1, std::chrono::milliseconds(10));
    } catch (const zmq::error_t& e) {
      if (e.num() != EINTR) spdlog::error("poll: {}", e.what());
    }
    const Millis now = now_ms();
    std::lock_guard lock(mutex_);
    receive_all(now);
    for (const WorkerId& dead : dispatcher_.expire(now))
      spdlog::warn("worker {} silent for {} ms: its jobs go back to the queue", printable(dead),
                   dispatcher_.settings().liveness_ms);
    if (shutdown_requested_) {
      for (const WorkerView& w : dispatcher_.workers()) {
        Outgoing bye{w.id, {}};
        bye.message.mutable_shutdown()->set_reason(shutdown_reason_);
        send(bye);
      }
      shutdown_requested_ = false;
    }
    for (const Outgoing& message : dispatcher_.outgoing(now)) send(message);
    if (dispatcher_.batch_done() || dispatcher_.failure()) changed_.notify_all();
    if (publish_ && now - last_publish >= 500) {
      publish_(dispatcher_);
      last_publish = now;
    }
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
      note_drop("malformed", id);
      continue;
    }
    if (frames[0].size() > kMaxWorkerMessageBytes) {
      note_drop("oversized", id);
      continue;
    }
    handle(id, frames[0].to_string(), now);
  }
}

void RemoteEvaluator::handle(const std::string& peer, const std::string& payload, Millis now) {
  wire::WorkerMessage message;
  if (!message.ParseFromString(payload) || message.kind_case() == wire::WorkerMessage::KIND_NOT_SET) {
    note_drop("malformed", peer);
    return;
  }
  switch (message.kind_case()) {
    case wire::WorkerMessage::kHello: {
      Outgoing reply{peer, dispatcher_.on_hello(peer, message.hello(), now)};
      if (reply.message.has_refused()) {  // counted by the dispatcher
        spdlog::warn("refused worker {}: {}", message.hello().name().substr(0, 200), reply.message.refused().reason());
      } else {
        spdlog::info("worker {} ({} threads) joined: {} connected", message.hello().name().substr(0, 200),
                     message.hello().threads(), dispatcher_.worker_count());
      }
      send(reply);
      return;
    }
    case wire::WorkerMessage::kResult:
    case wire::WorkerMessage::kHeartbeat:
      if (!dispatcher_.heard_from(peer, now)) {
        // a worker of an earlier coordinator on this port, or one counted dead: it must start afresh
        note_drop("unknown_peer", peer);
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
      spdlog::info("worker {} left: {} connected", printable(peer), dispatcher_.worker_count());
      return;
    default:
      note_drop("malformed", peer);
  }
}

void RemoteEvaluator::send(const Outgoing& message) {
  const std::string payload = message.message.SerializeAsString();
  try {
    zmq::message_t id(message.worker.data(), message.worker.size());
    if (!socket_->send(id, zmq::send_flags::sndmore | zmq::send_flags::dontwait) ||
        !socket_->send(zmq::buffer(payload), zmq::send_flags::dontwait)) {
      dispatcher_.remove_worker(message.worker, /*died=*/false);  // its queue is full: it is not keeping up
    }
  } catch (const zmq::error_t& e) {
    // EHOSTUNREACH: the peer's connection is gone (a killed worker); its jobs go back to the queue
    if (dispatcher_.worker_count() > 0) dispatcher_.remove_worker(message.worker, /*died=*/true);
    spdlog::debug("send to {}: {}", printable(message.worker), e.what());
  }
}

void RemoteEvaluator::note_drop(const std::string& reason, const std::string& peer) {
  dispatcher_.count_drop(reason);
  const Millis now = now_ms();
  Millis& last = last_drop_log_[reason];
  if (now - last < 1000) return;  // never flood the log
  last = now;
  spdlog::warn("dropped a frame from {}: {} ({} so far)", printable(peer), reason, dispatcher_.dropped().at(reason));
}

}  // namespace poet
