#pragma once
// The worker's side of the wire protocol (proto/wire.proto) as a state machine with no sockets and no clock of
// its own: each call takes what happened (a frame arrived, a job finished, time passed, a stop) and `now`, and
// returns what the socket loop must do. The loop (worker_loop) only moves bytes and jobs; every rule lives here
// and is tested with a fake clock.
//
//   greeting ── Welcome ──▶ welcomed ── nothing received for liveness_ms ──▶ waiting to reconnect
//      ▲ ▲                     │                                                   │
//      │ └── Rejoin: Hello ────┘                                                   │
//      └──── fresh socket, Hello (after a backoff of 250 ms, doubling to 4 s) ─────┘
//   greeting ── the handshake failed (a refused CURVE key, a peer of another protocol) ──▶ waiting to reconnect
//   Refused (exit 2), Shutdown (exit 0) or a stop (Goodbye, exit 0) ──▶ finished
//
// Greeting: Hello now and every second until a Welcome (a connection that brings none within greeting_timeout
// is closed and a fresh one opened after the backoff: libzmq can leave a refused handshake hanging) (sooner when a
// Hello could not be sent because the connection is not up yet); a Heartbeat answers the Welcome at once (ready for
// jobs). Welcomed: Heartbeat whenever nothing was sent for heartbeat_ms; a Rejoin (the coordinator restarted) drops the
// jobs and goes back to greeting with a Hello at once; a Job is decoded at once (θs into the cache, tasks checked) and
// either handed to the runner or answered with an error Result. Anything that fails to parse, is larger than the cap or
// comes when its kind makes no sense is counted and dropped, with a log line at most once a second. Without a Welcome
// for still_trying_first, and then after gaps that double up to still_trying_max, the loop is told to say that the
// worker is still trying, and where.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/formats/rollout_task_proto.h"
#include "common/protocol/wire_timing.h"
#include "wire.pb.h"
#include "worker/job_executor.h"

namespace poet::worker {

using Clock = std::chrono::steady_clock;
using TimePoint = Clock::time_point;
using Millis = std::chrono::milliseconds;

// The largest frame the worker reads (the socket's ZMQ_MAXMSGSIZE too): a job of a few thousand tasks is under
// a megabyte, so 64 MB only ever stops a hostile or broken peer.
inline constexpr size_t kMaxFrameBytes = size_t{64} << 20;

struct SessionSettings {
  uint32_t threads = 1;     // told to the coordinator in Hello
  std::string name;         // for people: "host:pid" by default (worker_command.cpp)
  std::string local_token;  // told in Hello: from the coordinator that started this worker (--local-workers)
  Millis hello_interval{1000};
  // A connection that brings no Welcome this long is replaced by a fresh one (a handshake libzmq left hanging).
  Millis greeting_timeout{wire_timing::kLivenessMs};
  Millis hello_retry{50};  // after a Hello that could not be sent (no connection yet)
  Millis first_backoff{250};
  Millis max_backoff{4000};
  Millis still_trying_first{2000};  // no Welcome this long after losing (or never having) one: say so
  Millis still_trying_max{60000};   // the gap between such lines doubles up to this
  size_t max_frame_bytes = kMaxFrameBytes;
};

// What the socket loop must do after a call, in this order. A call that ends the session sets exit_code; the
// loop performs the rest (e.g. sends the Goodbye) first.
struct Actions {
  bool abandon_jobs = false;  // stop the running job, drop the queued jobs and the outcomes not yet sent
  bool close_socket = false;  // the coordinator is gone: close the socket
  bool open_socket = false;   // make a fresh socket and connect it (before the sends below)
  std::vector<wire::WorkerMessage> send;
  std::vector<WorkerJob> run;          // hand to the job runner, in this order
  std::optional<Millis> still_trying;  // no Welcome for this long: log that the worker is still trying, and where
  std::optional<int> exit_code;        // leave, with this process exit code
};

enum class SessionState {
  kGreeting,            // Hello sent, no Welcome yet
  kWelcomed,            // taking jobs
  kWaitingToReconnect,  // no socket; a fresh one at reconnect_at()
  kFinished,            // Refused, Shutdown or stopped: nothing more
};

// Frames dropped since the start, by reason.
struct DropCounts {
  uint64_t oversized = 0;   // larger than max_frame_bytes
  uint64_t unparsable = 0;  // not a CoordinatorMessage
  uint64_t unexpected = 0;  // no kind, a kind the state does not expect, a multi-part message, a Job with no id
  uint64_t total() const { return oversized + unparsable + unexpected; }
};

class WorkerSession {
 public:
  explicit WorkerSession(SessionSettings settings);

  // The socket has just been opened: the first Hello.
  Actions start(TimePoint now);

  // One received single-part frame: checked, parsed and handled as on_message. Any frame, even one that is
  // dropped, shows that the coordinator is alive.
  Actions on_frame(std::string_view frame, TimePoint now);

  // A received message of several parts (the protocol has one part per message): dropped.
  Actions on_multipart(TimePoint now);

  Actions on_message(const wire::CoordinatorMessage& message, TimePoint now);

  // The runner finished a job: its Result, when the session still talks to the coordinator it came from.
  Actions on_job_finished(const JobOutcome& outcome, TimePoint now);

  // A message from the last Actions could not be sent (no connection, or the socket refused it).
  Actions on_send_failed(const wire::WorkerMessage& message, TimePoint now);

  // The socket could not be opened or connected (say, the coordinator's host name does not resolve yet).
  Actions on_connect_failed(TimePoint now);

  // The socket's handshake failed (a refused CURVE key, CURVE on one side only, a peer of another protocol).
  // libzmq does not try such a connection again, so: a fresh socket after the backoff.
  Actions on_handshake_failed(TimePoint now);

  // Time passed: Hello again, Heartbeat, the liveness check, the reconnection after a backoff.
  Actions on_tick(TimePoint now);

  // SIGTERM or SIGINT: abandon the work, Goodbye (when welcomed), exit 0.
  Actions on_stop(TimePoint now, std::string reason);

  // When on_tick next has something to do (TimePoint::max() when finished).
  TimePoint next_deadline() const;

  SessionState state() const { return state_; }
  const DropCounts& drops() const { return drops_; }
  Millis heartbeat_interval() const { return heartbeat_; }
  Millis liveness() const { return liveness_; }
  Millis backoff() const { return backoff_; }  // the wait before the next reconnection
  size_t cached_thetas() const { return thetas_.size(); }

 private:
  wire::WorkerMessage hello() const;
  void send(Actions& actions, wire::WorkerMessage message, TimePoint now);
  void accept_job(const wire::Job& job, Actions& actions, TimePoint now);
  void drop_work(Actions& actions);  // the jobs in hand, the θ cache and the batch go
  // no coordinator: close the socket, drop the work, and try again after the backoff (which then doubles)
  void wait_to_reconnect(Actions& actions, TimePoint now);
  // the coordinator is gone (or never came): the still-trying lines count from now
  void lost_coordinator(TimePoint now);
  void finish(Actions& actions, int exit_code);
  void drop(uint64_t DropCounts::*reason, std::string_view what, TimePoint now);

  SessionSettings settings_;
  SessionState state_ = SessionState::kGreeting;
  Millis heartbeat_{wire_timing::kHeartbeatMs};  // from Welcome
  Millis liveness_{wire_timing::kLivenessMs};    // from Welcome
  Millis backoff_;
  TimePoint next_hello_{};
  TimePoint last_sent_{};
  TimePoint last_received_{};
  TimePoint welcomed_at_{};
  TimePoint reconnect_at_{};
  TimePoint greeting_since_{};    // this connection's first Hello
  bool connect_failing_ = false;  // sockets could not be opened since the last Welcome: their lines at debug
  TimePoint unwelcomed_since_{};  // the still-trying lines: since when (epoch: not started), the next, the gap after
  TimePoint next_still_trying_{};
  Millis still_trying_gap_{};
  // θs of the current batch only: a Job of another batch clears them (queued jobs hold their own θs)
  ThetaCache thetas_;
  std::optional<uint64_t> batch_;
  DropCounts drops_;
  uint64_t drops_unlogged_ = 0;
  std::optional<TimePoint> last_drop_log_;
};

// Welcome's timings as the worker uses them: 0 or absent means the defaults (1 s, 5 s); values are kept in
// [10 ms, 1 h], and liveness at least twice the heartbeat interval, so a single late heartbeat is not a death.
std::pair<Millis, Millis> welcome_timings(const wire::Welcome& welcome);

}  // namespace poet::worker
