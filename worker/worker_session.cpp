#include "worker/worker_session.h"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <utility>

#include "common/program/build_fingerprint.h"

namespace poet::worker {
namespace {

using namespace std::chrono_literals;

constexpr Millis kDefaultHeartbeat{wire_timing::kHeartbeatMs};
constexpr Millis kDefaultLiveness{wire_timing::kLivenessMs};
constexpr Millis kMinTiming = 10ms;
constexpr Millis kMaxTiming = 3'600'000ms;
constexpr auto kDropLogInterval = 1s;

long long ms(Millis d) { return static_cast<long long>(d.count()); }

}  // namespace

std::pair<Millis, Millis> welcome_timings(const wire::Welcome& welcome) {
  auto pick = [](bool has, uint32_t value, Millis fallback) {
    if (!has || value == 0) return fallback;
    return std::clamp(Millis(value), kMinTiming, kMaxTiming);
  };
  const Millis heartbeat = pick(welcome.has_heartbeat_ms(), welcome.heartbeat_ms(), kDefaultHeartbeat);
  const Millis liveness = pick(welcome.has_liveness_ms(), welcome.liveness_ms(), kDefaultLiveness);
  return {heartbeat, std::max(liveness, 2 * heartbeat)};
}

WorkerSession::WorkerSession(SessionSettings settings)
    : settings_(std::move(settings)), backoff_(settings_.first_backoff) {}

wire::WorkerMessage WorkerSession::hello() const {
  wire::WorkerMessage message;
  wire::Hello& hello = *message.mutable_hello();
  hello.set_protocol_version(wire::PROTOCOL_VERSION);
  hello.set_fingerprint_digest(build_fingerprint_digest());
  hello.set_fingerprint(build_fingerprint());
  hello.set_arithmetic_digest(arithmetic_digest());
  hello.set_arithmetic(arithmetic_text());
  hello.set_threads(settings_.threads);
  hello.set_name(settings_.name);
  if (!settings_.local_token.empty()) hello.set_local_token(settings_.local_token);
  return message;
}

void WorkerSession::send(Actions& actions, wire::WorkerMessage message, TimePoint now) {
  actions.send.push_back(std::move(message));
  last_sent_ = now;
}

void WorkerSession::lost_coordinator(TimePoint now) {
  unwelcomed_since_ = now;
  still_trying_gap_ = settings_.still_trying_first;
  next_still_trying_ = now + still_trying_gap_;
}

Actions WorkerSession::start(TimePoint now) {
  Actions actions;
  state_ = SessionState::kGreeting;
  lost_coordinator(now);
  send(actions, hello(), now);
  next_hello_ = now + settings_.hello_interval;
  greeting_since_ = now;
  return actions;
}

Actions WorkerSession::on_frame(std::string_view frame, TimePoint now) {
  if (state_ != SessionState::kGreeting && state_ != SessionState::kWelcomed) return {};
  last_received_ = now;  // a frame of any sort shows the coordinator is there
  if (frame.size() > settings_.max_frame_bytes) {
    drop(&DropCounts::oversized,
         fmt::format("a frame of {} bytes (the cap is {})", frame.size(), settings_.max_frame_bytes), now);
    return {};
  }
  wire::CoordinatorMessage message;
  if (!message.ParseFromArray(frame.data(), static_cast<int>(frame.size()))) {
    drop(&DropCounts::unparsable, fmt::format("{} bytes that are not a CoordinatorMessage", frame.size()), now);
    return {};
  }
  return on_message(message, now);
}

Actions WorkerSession::on_multipart(TimePoint now) {
  if (state_ != SessionState::kGreeting && state_ != SessionState::kWelcomed) return {};
  last_received_ = now;
  drop(&DropCounts::unexpected, "a message of several frames", now);
  return {};
}

Actions WorkerSession::on_message(const wire::CoordinatorMessage& message, TimePoint now) {
  Actions actions;
  if (state_ != SessionState::kGreeting && state_ != SessionState::kWelcomed) return actions;
  last_received_ = now;
  const bool welcomed = state_ == SessionState::kWelcomed;
  switch (message.kind_case()) {
    case wire::CoordinatorMessage::kWelcome: {
      std::tie(heartbeat_, liveness_) = welcome_timings(message.welcome());
      if (!welcomed) {
        state_ = SessionState::kWelcomed;
        welcomed_at_ = now;
        connect_failing_ = false;
        spdlog::info("welcomed by the coordinator: heartbeat every {} ms, liveness {} ms", ms(heartbeat_),
                     ms(liveness_));
        wire::WorkerMessage ready;  // the coordinator sends jobs once the worker has answered its Welcome
        ready.mutable_heartbeat();
        send(actions, std::move(ready), now);
      } else {
        // a second Welcome answers a Hello repeated before the first arrived
        spdlog::debug("Welcome again: heartbeat every {} ms, liveness {} ms", ms(heartbeat_), ms(liveness_));
      }
      break;
    }
    case wire::CoordinatorMessage::kRefused:
      spdlog::error("refused by the coordinator: {}", message.refused().reason());
      finish(actions, 2);
      break;
    case wire::CoordinatorMessage::kJob:
      if (!welcomed) {
        drop(&DropCounts::unexpected, "a Job before Welcome", now);
        break;
      }
      accept_job(message.job(), actions, now);
      break;
    case wire::CoordinatorMessage::kHeartbeat:
      if (!welcomed) drop(&DropCounts::unexpected, "a Heartbeat before Welcome", now);
      break;
    case wire::CoordinatorMessage::kShutdown:
      spdlog::info("the coordinator shuts the worker down: {}", message.shutdown().reason());
      finish(actions, 0);
      break;
    case wire::CoordinatorMessage::kRejoin:
      if (!welcomed) break;  // it answers a message sent before this Hello: the Welcome is on its way
      spdlog::warn("the coordinator does not know this worker ({}): dropping its jobs, Hello again",
                   message.rejoin().reason().substr(0, 200));
      drop_work(actions);
      state_ = SessionState::kGreeting;
      lost_coordinator(now);
      send(actions, hello(), now);
      next_hello_ = now + settings_.hello_interval;
      greeting_since_ = now;
      break;
    case wire::CoordinatorMessage::KIND_NOT_SET:
      drop(&DropCounts::unexpected, "a message of no known kind", now);
      break;
  }
  return actions;
}

void WorkerSession::accept_job(const wire::Job& job, Actions& actions, TimePoint now) {
  if (!job.has_job_id()) {
    drop(&DropCounts::unexpected, "a Job with no job_id", now);
    return;
  }
  // a job of another batch: the previous batch's θs go (jobs already queued hold theirs)
  if (!batch_ || *batch_ != job.batch_id()) {
    thetas_.clear();
    batch_ = job.batch_id();
  }
  auto refuse = [&](std::string error, bool missing_theta) {
    if (missing_theta) {
      spdlog::debug("job {}: {}", job.job_id(), error);
    } else {
      spdlog::warn("job {} refused: {}", job.job_id(), error);
    }
    wire::WorkerMessage message;
    wire::Result& result = *message.mutable_result();
    result.set_job_id(job.job_id());
    result.set_error(std::move(error));
    if (missing_theta) result.set_missing_theta(true);
    send(actions, std::move(message), now);
  };

  // θs first, then every task checked before any runs: a job runs whole or not at all
  for (int i = 0; i < job.thetas_size(); ++i) {
    if (auto error = add_theta(job.thetas(i), thetas_)) return refuse(fmt::format("thetas[{}].{}", i, *error), false);
  }
  WorkerJob decoded{.job_id = job.job_id(), .batch_id = job.batch_id(), .tasks = {}};
  decoded.tasks.reserve(static_cast<size_t>(job.tasks_size()));
  for (int i = 0; i < job.tasks_size(); ++i) {
    const wire::Task& task = job.tasks(i);
    if (task.has_theta_hash() && !thetas_.contains(task.theta_hash())) {
      return refuse(
          fmt::format("tasks[{}].theta_hash: no θ {:016x} was sent in batch {}", i, task.theta_hash(), job.batch_id()),
          true);
    }
    Expected<RolloutTask> decoded_task = task_from_wire(task, thetas_);
    if (!decoded_task) return refuse(fmt::format("tasks[{}].{}", i, decoded_task.error()), false);
    decoded.tasks.push_back(std::move(*decoded_task));
  }
  spdlog::debug("job {} (batch {}): {} tasks queued", job.job_id(), job.batch_id(), decoded.tasks.size());
  actions.run.push_back(std::move(decoded));
}

Actions WorkerSession::on_job_finished(const JobOutcome& outcome, TimePoint now) {
  Actions actions;
  if (state_ != SessionState::kWelcomed) return actions;  // a job of a coordinator the worker has left
  wire::WorkerMessage message;
  wire::Result& result = *message.mutable_result();
  result.set_job_id(outcome.job_id);
  if (outcome.error) {
    spdlog::warn("job {} failed: {}", outcome.job_id, *outcome.error);
    result.set_error(*outcome.error);
  } else {
    for (const RolloutResult& r : outcome.results) *result.add_results() = to_wire(r);
  }
  send(actions, std::move(message), now);
  return actions;
}

Actions WorkerSession::on_send_failed(const wire::WorkerMessage& message, TimePoint now) {
  switch (message.kind_case()) {
    case wire::WorkerMessage::kHello:
      // the connection is not up yet: try again soon rather than in a second
      if (state_ == SessionState::kGreeting) next_hello_ = std::min(next_hello_, now + settings_.hello_retry);
      break;
    case wire::WorkerMessage::kResult:
      spdlog::warn("the result of job {} could not be sent (no connection); the coordinator re-queues the job",
                   message.result().job_id());
      break;
    default:
      break;  // a heartbeat or a goodbye lost with the connection
  }
  return {};
}

Actions WorkerSession::on_handshake_failed(TimePoint now) {
  Actions actions;
  if (state_ != SessionState::kGreeting && state_ != SessionState::kWelcomed) return actions;
  if (state_ == SessionState::kWelcomed) lost_coordinator(now);
  wait_to_reconnect(actions, now);
  return actions;
}

Actions WorkerSession::on_connect_failed(TimePoint now) {
  Actions actions;
  if (state_ == SessionState::kFinished) return actions;
  if (unwelcomed_since_ == TimePoint{}) lost_coordinator(now);  // the first socket failed: start() never ran
  // said once a streak (a coordinator's endpoint file missing for an hour fails every few seconds); the
  // still-trying lines say how long it has lasted
  spdlog::log(connect_failing_ ? spdlog::level::debug : spdlog::level::warn,
              "could not connect to the coordinator; trying again in {} ms", ms(backoff_));
  connect_failing_ = true;
  wait_to_reconnect(actions, now);
  return actions;
}

void WorkerSession::drop_work(Actions& actions) {
  actions.abandon_jobs = true;
  thetas_.clear();
  batch_.reset();
}

void WorkerSession::wait_to_reconnect(Actions& actions, TimePoint now) {
  drop_work(actions);
  actions.close_socket = true;
  state_ = SessionState::kWaitingToReconnect;
  reconnect_at_ = now + backoff_;
  backoff_ = std::min(2 * backoff_, settings_.max_backoff);
}

Actions WorkerSession::on_tick(TimePoint now) {
  Actions actions;
  const bool unwelcomed = state_ == SessionState::kGreeting || state_ == SessionState::kWaitingToReconnect;
  if (unwelcomed && now >= next_still_trying_) {
    actions.still_trying = std::chrono::floor<Millis>(now - unwelcomed_since_);
    still_trying_gap_ = std::min(2 * still_trying_gap_, settings_.still_trying_max);
    next_still_trying_ = now + still_trying_gap_;
  }
  switch (state_) {
    case SessionState::kGreeting:
      if (now - greeting_since_ >= settings_.greeting_timeout) {
        spdlog::debug("no Welcome on this connection for {} ms: a fresh one in {} ms", ms(settings_.greeting_timeout),
                      ms(backoff_));
        wait_to_reconnect(actions, now);
        break;
      }
      if (now >= next_hello_) {
        send(actions, hello(), now);
        next_hello_ = now + settings_.hello_interval;
      }
      break;
    case SessionState::kWelcomed:
      if (now - last_received_ >= liveness_) {
        spdlog::warn("nothing from the coordinator for {} ms: it is gone; reconnecting in {} ms", ms(liveness_),
                     ms(backoff_));
        lost_coordinator(now);
        wait_to_reconnect(actions, now);
        break;
      }
      // a connection that stayed up a whole liveness window earns a fresh backoff
      if (now - welcomed_at_ >= liveness_) backoff_ = settings_.first_backoff;
      if (now - last_sent_ >= heartbeat_) {
        wire::WorkerMessage heartbeat;
        heartbeat.mutable_heartbeat();
        send(actions, std::move(heartbeat), now);
      }
      break;
    case SessionState::kWaitingToReconnect:
      if (now >= reconnect_at_) {
        actions.open_socket = true;
        state_ = SessionState::kGreeting;
        send(actions, hello(), now);
        next_hello_ = now + settings_.hello_interval;
        greeting_since_ = now;
        spdlog::log(connect_failing_ ? spdlog::level::debug : spdlog::level::info, "connecting again; Hello");
      }
      break;
    case SessionState::kFinished:
      break;
  }
  return actions;
}

Actions WorkerSession::on_stop(TimePoint now, std::string reason) {
  Actions actions;
  if (state_ == SessionState::kFinished) return actions;
  if (state_ == SessionState::kWelcomed) {
    wire::WorkerMessage goodbye;
    goodbye.mutable_goodbye()->set_reason(reason);
    send(actions, std::move(goodbye), now);
  }
  spdlog::info("stopping: {}", reason);
  finish(actions, 0);
  return actions;
}

void WorkerSession::finish(Actions& actions, int exit_code) {
  drop_work(actions);
  actions.exit_code = exit_code;
  state_ = SessionState::kFinished;
}

TimePoint WorkerSession::next_deadline() const {
  switch (state_) {
    case SessionState::kGreeting:
      return std::min(next_hello_, next_still_trying_);
    case SessionState::kWelcomed:
      return std::min(last_sent_ + heartbeat_, last_received_ + liveness_);
    case SessionState::kWaitingToReconnect:
      return std::min(reconnect_at_, next_still_trying_);
    case SessionState::kFinished:
      break;
  }
  return TimePoint::max();
}

void WorkerSession::drop(uint64_t DropCounts::*reason, std::string_view what, TimePoint now) {
  ++(drops_.*reason);
  ++drops_unlogged_;
  if (last_drop_log_ && now - *last_drop_log_ < kDropLogInterval) return;
  spdlog::warn("dropped {} from the coordinator ({} frames dropped since the last such line, {} in all)", what,
               drops_unlogged_, drops_.total());
  drops_unlogged_ = 0;
  last_drop_log_ = now;
}

}  // namespace poet::worker
