#pragma once
// The status socket: HTTP/1.1 (cpp-httplib) over a StatusBoard, on threads of its own — one that accepts and a
// small pool that answers. The endpoints are status_routes.h's. Bounded everywhere: read and write timeouts
// per connection, a short keep-alive, a small request-body limit and a fixed pool. A client that stops sending
// holds one pool thread for read_timeout (then gets a 400) plus the keep-alive; other requests go to the other
// threads, or wait that long when every thread is held. A client that trickles a byte at a time can hold a
// thread longer (httplib 0.11 has no deadline for a whole request). Nothing a client does touches the run: the
// board's lock is held only to copy a pointer. SIGPIPE is blocked in the server's threads, so a client that
// hangs up mid-answer cannot end the process. Headers, URI and body are limited (414, 413). TCP_NODELAY: a kept-alive
// connection's requests are answered at once, not after the client's delayed ACK.
//
// Not in this header: httplib.h (whose <resolv.h> defines `_res`, a name Eigen uses), so any file may include it.
//
// Use: StatusBoard board(run_dir); StatusServer server(board); Expected<int> port = server.start("127.0.0.1:8580");
// The board must outlive the server. start/stop/port are for one owning thread.

#include <chrono>
#include <cstddef>
#include <memory>
#include <string>

#include "expected.h"
#include "status/status_board.h"
#include "status_client/host_port.h"
#include "status_client/status_defaults.h"

namespace poet {

inline constexpr char kDefaultStatusAddress[] = "127.0.0.1:0";  // loopback, an ephemeral port

struct StatusServerOptions {
  int threads = 3;                                // the pool answering requests, in [1, 16]
  std::chrono::milliseconds read_timeout{3000};   // a request's bytes must keep coming at least this often
  std::chrono::milliseconds write_timeout{3000};  // and a response's bytes must be taken
  int keep_alive_seconds = 2;                     // an idle kept-alive connection is closed after this
  size_t keep_alive_max_requests = 100;           // requests on one connection
  size_t payload_max_bytes = 16 * 1024;           // a request body beyond this is refused (413)
  bool health_only = false;                       // answer /healthz alone (404 elsewhere): the probes' listener
};

// The probes' listener (poet-coordinator --health-address): /healthz alone, on a port of its own, because the
// status socket's pool can be held by its clients (200 that trickle header lines hold it for as long as they
// like) and an orchestrator that cannot reach /healthz restarts the coordinator. Short timeouts: a probe sends
// its request at once.
StatusServerOptions health_listener_options();

class StatusServer {
 public:
  explicit StatusServer(StatusBoard& board, StatusServerOptions options = {});
  ~StatusServer();  // stop()
  StatusServer(const StatusServer&) = delete;
  StatusServer& operator=(const StatusServer&) = delete;

  // Binds address ("HOST:PORT"; port 0 picks an ephemeral one) and serves on a new thread. Returns the bound
  // port once the server accepts connections, or an error naming the address (bad address, in use, not local,
  // already started).
  Expected<int> start(const std::string& address = kDefaultStatusAddress);

  // Closes the socket, lets the requests being answered finish (each bounded by the timeouts) and joins the
  // threads. Idempotent; after it, start may be called again.
  void stop();

  // The bound port while started, else 0.
  int port() const { return port_; }

 private:
  struct Impl;
  StatusBoard& board_;
  const StatusServerOptions options_;
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
};

}  // namespace poet
