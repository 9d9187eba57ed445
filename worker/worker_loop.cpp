#include "worker/worker_loop.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <system_error>
#include <utility>
#include <zmq.hpp>

#include "common/plumbing/endpoint_file.h"
#include "worker/handshake_failure.h"

namespace poet::worker {
namespace {

using namespace std::chrono_literals;

// The longest poll: the loop wakes at least this often even with nothing to do (a safety net; deadlines and the
// wake pipe normally wake it).
constexpr Millis kMaxPollWait = 100ms;
// Messages read in one turn before timers and finished jobs get their turn.
constexpr int kMaxFramesPerTurn = 256;
// How long closing the socket may wait to deliver a Goodbye.
constexpr int kGoodbyeLingerMs = 500;

const char* kind_name(const wire::WorkerMessage& message) {
  switch (message.kind_case()) {
    case wire::WorkerMessage::kHello:
      return "Hello";
    case wire::WorkerMessage::kResult:
      return "Result";
    case wire::WorkerMessage::kHeartbeat:
      return "Heartbeat";
    case wire::WorkerMessage::kGoodbye:
      return "Goodbye";
    case wire::WorkerMessage::KIND_NOT_SET:
      break;
  }
  return "message";
}

class SocketLoop {
 public:
  SocketLoop(const LoopSettings& settings, JobExecutor& jobs, WakePipe& wake, const std::atomic<bool>& stop)
      : settings_(settings),
        jobs_(jobs),
        wake_(wake),
        stop_(stop),
        endpoint_(settings.endpoint),
        curve_(settings.curve),
        session_(settings.session) {}
  ~SocketLoop() { close_socket(); }

  int run() {
    std::optional<int> code =
        connect() ? apply(session_.start(Clock::now())) : apply(session_.on_connect_failed(Clock::now()));
    while (!code) {
      if (stop_) {
        code = apply(session_.on_stop(Clock::now(), "stopped by a signal"));
        return code.value_or(0);
      }
      if (!poll()) continue;  // interrupted: look at the stop flag again
      wake_.drain();
      if (stop_) continue;
      code = read_handshakes();
      if (!code) code = receive();
      if (code) break;
      for (const JobOutcome& outcome : jobs_.take_finished()) {
        code = apply(session_.on_job_finished(outcome, Clock::now()));
        if (code) break;
      }
      if (!code) code = apply(session_.on_tick(Clock::now()));
    }
    return *code;
  }

 private:
  // With --coordinator-file, where the coordinator is now (it may have moved: a chained run's next job on another
  // node). False when the file cannot be read or does not fit this worker's keys; said when that changes.
  bool follow_endpoint_file() {
    if (settings_.endpoint_file.empty()) return true;
    Expected<CoordinatorEndpoint> read = read_endpoint_file(settings_.endpoint_file);
    std::string problem;
    if (!read) {
      problem = read.error();
    } else if (!read->curve_public_key.empty() && curve_ && !settings_.curve->server_public_key.empty() &&
               read->curve_public_key != settings_.curve->server_public_key) {
      // a key given in --curve-keys DIR is the one trusted: whoever can write the run directory must not be able
      // to send this worker to another coordinator
      problem =
          "its curve_public_key is not the coordinator.key of --curve-keys (remove that file to take the key "
          "from the endpoint file)";
    } else if (!read->curve_public_key.empty() && !curve_) {
      problem = "the coordinator uses CURVE (the file has its key): give --curve-keys DIR with this worker's pair";
    } else if (read->curve_public_key.empty() && curve_ && curve_->server_public_key.empty()) {
      problem = "the file has no curve_public_key and --curve-keys DIR has no coordinator.key";
    }
    if (!problem.empty()) {
      if (problem != endpoint_file_problem_)
        spdlog::warn("--coordinator-file {}: {}; trying again", settings_.endpoint_file, problem);
      endpoint_file_problem_ = problem;
      last_problem_ = settings_.endpoint_file + ": " + problem;
      return false;
    }
    endpoint_file_problem_.clear();
    if (read->endpoint != endpoint_)
      spdlog::info("{} gives the coordinator at {}", settings_.endpoint_file, read->endpoint);
    endpoint_ = read->endpoint;
    if (curve_ && !read->curve_public_key.empty()) curve_->server_public_key = read->curve_public_key;
    return true;
  }

  // A fresh DEALER connected to the coordinator; false (and no socket) when the endpoint cannot be connected.
  bool connect() {
    close_socket();
    if (!follow_endpoint_file()) return false;
    try {
      zmq::socket_t socket(context_, zmq::socket_type::dealer);
      socket.set(zmq::sockopt::linger, 0);
      if (curve_) {
        socket.set(zmq::sockopt::curve_serverkey, curve_->server_public_key);
        socket.set(zmq::sockopt::curve_publickey, curve_->public_key);
        socket.set(zmq::sockopt::curve_secretkey, curve_->secret_key);
      }
      watch_handshakes(socket);
      socket.set(zmq::sockopt::maxmsgsize, static_cast<int64_t>(kMaxFrameBytes));
      // no queueing for a peer that is not connected: a Hello sent then fails at once (and is retried) instead
      // of piling up and arriving in a burst when the coordinator comes up
      socket.set(zmq::sockopt::immediate, 1);
      socket.connect(endpoint_);
      socket_ = std::move(socket);
      spdlog::debug("connecting to {}", endpoint_);
      return true;
    } catch (const zmq::error_t& e) {
      spdlog::warn("cannot connect to {}: {}", endpoint_, e.what());
      socket_.reset();
      return false;
    }
  }

  // Closes the socket and the PAIR its events arrive on, the monitor stopped first. libzmq's I/O thread sends each
  // event to the monitor with a blocking send: one sent once this end of the PAIR is closed (the DISCONNECTED that
  // follows the HANDSHAKE_FAILED_AUTH the session reacted to, or any event of a connection still going when the
  // socket is closed) would wait forever, and with it the context's only I/O thread, that every later socket
  // needs: no connection would be made again, and no event come. Stopped (under libzmq's monitor lock), the socket
  // sends no more events.
  void close_socket() {
    if (socket_ && monitor_) zmq_socket_monitor(socket_->handle(), nullptr, 0);
    socket_.reset();
    monitor_.reset();
  }

  // The connections and handshakes of `socket` arrive on monitor_ (ZeroMQ's socket monitor over inproc).
  void watch_handshakes(zmq::socket_t& socket) {
    handshaking_ = false;
    const std::string address = "inproc://handshakes-" + std::to_string(++monitors_);
    const int events = ZMQ_EVENT_HANDSHAKE_FAILED_AUTH | ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL |
                       ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL | ZMQ_EVENT_HANDSHAKE_SUCCEEDED | ZMQ_EVENT_CONNECTED |
                       ZMQ_EVENT_DISCONNECTED | ZMQ_EVENT_CONNECT_RETRIED;
    if (zmq_socket_monitor(socket.handle(), address.c_str(), events) != 0) return;  // only the log line is lost
    zmq::socket_t monitor(context_, zmq::socket_type::pair);
    monitor.set(zmq::sockopt::linger, 0);
    monitor.connect(address);
    monitor_ = std::move(monitor);
  }

  // Reads the monitor's events. A failed handshake (or a peer that hangs up during one) is logged, once for each
  // new cause until a handshake succeeds, and handed to the session: libzmq does not retry such a connection, so
  // the session opens a fresh socket after its backoff. What happened last is kept for the still-trying lines.
  std::optional<int> read_handshakes() {
    for (int n = 0; monitor_ && n < kMaxFramesPerTurn; ++n) {
      zmq::message_t event;
      if (!monitor_->recv(event, zmq::recv_flags::dontwait)) break;
      zmq::message_t address;
      if (event.more() && !monitor_->recv(address, zmq::recv_flags::dontwait)) break;
      if (event.size() < 6) continue;
      uint16_t id = 0;
      uint32_t value = 0;
      std::memcpy(&id, event.data(), sizeof id);
      std::memcpy(&value, static_cast<const char*>(event.data()) + 2, sizeof value);
      switch (id) {
        case ZMQ_EVENT_CONNECT_RETRIED:
          last_problem_ = "nothing accepts connections there";
          continue;
        case ZMQ_EVENT_CONNECTED:
          handshaking_ = true;
          continue;
        case ZMQ_EVENT_HANDSHAKE_SUCCEEDED:
          handshaking_ = false;
          logged_failure_.clear();
          last_problem_ = "connected, but no Welcome yet";
          continue;
        case ZMQ_EVENT_DISCONNECTED:
          if (!handshaking_) continue;  // a connection that worked: the session's liveness rule handles it
          id = ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL;
          break;
        default:
          break;
      }
      handshaking_ = false;
      const std::optional<std::string> failure = handshake_failure(id, value, curve_.has_value(), endpoint_);
      if (!failure) continue;
      last_problem_ = *failure;
      if (*failure != logged_failure_) spdlog::error("{}; trying again", *failure);
      logged_failure_ = *failure;
      return apply(session_.on_handshake_failed(Clock::now()));
    }
    return std::nullopt;
  }

  // Waits for a frame, a wake-up or the next deadline. False when interrupted.
  bool poll() {
    zmq_pollitem_t items[3] = {
        {nullptr, wake_.read_fd(), ZMQ_POLLIN, 0}, {nullptr, 0, ZMQ_POLLIN, 0}, {nullptr, 0, ZMQ_POLLIN, 0}};
    size_t count = 1;
    if (socket_) items[count++].socket = socket_->handle();
    if (monitor_) items[count++].socket = monitor_->handle();
    const auto until_deadline = session_.next_deadline() - Clock::now();
    const Millis wait = std::clamp(std::chrono::ceil<Millis>(until_deadline), Millis(0), kMaxPollWait);
    try {
      zmq::poll(items, count, wait);
      return true;
    } catch (const zmq::error_t& e) {
      if (e.num() == EINTR) return false;
      throw;
    }
  }

  // Reads the frames waiting on the socket, each handed to the session.
  std::optional<int> receive() {
    for (int n = 0; n < kMaxFramesPerTurn && socket_; ++n) {
      zmq::message_t frame;
      try {
        if (!socket_->recv(frame, zmq::recv_flags::dontwait)) break;
        Actions actions;
        if (frame.more()) {
          // the parts of a message arrive together: read and drop the rest of it
          bool more = true;
          while (more) {
            zmq::message_t part;
            if (!socket_->recv(part, zmq::recv_flags::dontwait)) break;
            more = part.more();
          }
          actions = session_.on_multipart(Clock::now());
        } else {
          actions = session_.on_frame(frame.to_string_view(), Clock::now());
        }
        if (auto code = apply(std::move(actions))) return code;
      } catch (const zmq::error_t& e) {
        if (e.num() == EINTR) break;
        throw;
      }
    }
    return std::nullopt;
  }

  bool send(const wire::WorkerMessage& message) {
    if (!socket_) return false;
    const std::string bytes = message.SerializeAsString();
    try {
      if (socket_->send(zmq::buffer(bytes), zmq::send_flags::dontwait)) return true;
      spdlog::trace("{} not sent: no connection to the coordinator", kind_name(message));
    } catch (const zmq::error_t& e) {
      spdlog::warn("{} not sent: {}", kind_name(message), e.what());
    }
    return false;
  }

  // Does what the session asked, in the order Actions documents.
  std::optional<int> apply(Actions actions) {
    if (actions.still_trying) {
      spdlog::warn("still trying to reach the coordinator at {}: no Welcome for {} s{}",
                   endpoint_.empty() ? "the endpoint " + settings_.endpoint_file + " names" : endpoint_,
                   std::chrono::duration_cast<std::chrono::seconds>(*actions.still_trying).count(),
                   last_problem_.empty() ? "" : " (" + last_problem_ + ")");
    }
    if (actions.abandon_jobs) jobs_.abandon();
    if (actions.close_socket) close_socket();
    if (actions.open_socket && !connect()) return apply(session_.on_connect_failed(Clock::now()));
    bool sent = false;
    for (const wire::WorkerMessage& message : actions.send) {
      if (send(message)) {
        sent = true;
      } else {
        session_.on_send_failed(message, Clock::now());
      }
    }
    for (WorkerJob& job : actions.run) jobs_.submit(std::move(job));
    if (actions.exit_code) {
      // the last message (a Goodbye) gets a moment to leave; linger 0 would discard it
      if (socket_ && sent) socket_->set(zmq::sockopt::linger, kGoodbyeLingerMs);
      close_socket();
      return actions.exit_code;
    }
    return std::nullopt;
  }

  const LoopSettings& settings_;
  JobExecutor& jobs_;
  WakePipe& wake_;
  const std::atomic<bool>& stop_;
  zmq::context_t context_{1};
  std::optional<zmq::socket_t> socket_;   // after the context: closed before it
  std::optional<zmq::socket_t> monitor_;  // the socket's handshake events
  int monitors_ = 0;
  bool handshaking_ = false;    // connected, the handshake not over
  std::string logged_failure_;  // the last handshake failure logged, until one succeeds
  std::string last_problem_;    // what happened last on the way to a Welcome, for the still-trying lines
  std::string endpoint_;        // the coordinator's: --connect, or as --coordinator-file said last
  std::optional<CurveClient> curve_;   // the same for the coordinator's key
  std::string endpoint_file_problem_;  // what was wrong with --coordinator-file, said once until it changes
  WorkerSession session_;
};

}  // namespace

int run_worker(const LoopSettings& settings, JobExecutor& jobs, WakePipe& wake, const std::atomic<bool>& stop) {
  SocketLoop loop(settings, jobs, wake, stop);
  return loop.run();
}

}  // namespace poet::worker
