#pragma once
// The status socket: HTTP/1.1 (libmicrohttpd) over a StatusBoard, on threads of its own — a few, each with its own
// epoll loop. The endpoints are status_routes.h's. Event-driven because of slow clients: a connection that sends
// its request a byte at a time holds a slot and a small buffer, never a thread (cpp-httplib, used before, gave each
// connection a pool thread until its request was whole, and has no deadline for a whole request). A connection idle
// for idle_timeout is closed. The slots are capped (caps: in all, and from one address), and a crowd of slow
// connections under every cap still keeps no one out: a new connection past a cap sheds the oldest one of its
// address, else the oldest of all (connection_shedder.h), closed without an answer; so /healthz and /status answer
// within milliseconds whatever the number of slow clients and however they spread over addresses, and a listener
// holds at most its caps' worth of descriptors (descriptors_needed). Headers and URI are limited (414 past 8 KB,
// libmicrohttpd's own error past its 32 KB buffer), and so are a query (400 past 64 parameters, refused before
// libmicrohttpd parses them: it would close the connection unanswered when they fill its memory pool) and a body (413).
// A request line that cannot be parsed gets libmicrohttpd's own 400 (an HTML body) or, when it is not a request line at
// all (no space in it: binary garbage), a closed connection: libmicrohttpd 0.9.75 parses the request line before
// calling anything of ours, and closes such a line unanswered with no way for us to answer instead. Every answer of a
// route has a JSON body. Nothing a client does touches the run: the board's lock is held only to copy a pointer. Sends
// use MSG_NOSIGNAL, so a client that hangs up mid-answer cannot end the process.
//
// Use: StatusBoard board(run_dir); StatusServer server(board); Expected<int> port = server.start("127.0.0.1:8580");
// The board must outlive the server. start/stop/port are for one owning thread.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "common/plumbing/expected.h"
#include "common/plumbing/host_port.h"
#include "common/protocol/status_defaults.h"
#include "coordinator/status/connection_shedder.h"
#include "coordinator/status/status_board.h"

namespace poet {

inline constexpr char kDefaultStatusAddress[] = "127.0.0.1:0";  // loopback, an ephemeral port
// A request URI longer than this is refused (414), before any route sees it.
inline constexpr size_t kMaxUriBytes = 8192;
// A query with more parameters than this is refused (400): the routes read two at most.
inline constexpr size_t kMaxQueryParams = 64;

struct StatusServerOptions {
  int threads = 3;  // the loops answering requests, in [1, 16]: a slow answer (a picture) holds one
  // a connection that neither sends nor takes a byte this long is closed (whole seconds, at least one)
  std::chrono::seconds idle_timeout{3};
  size_t payload_max_bytes = 16 * 1024;  // a request body beyond this is refused (413)
  bool health_only = false;              // answer /healthz alone (404 elsewhere): the probes' listener
  // connections held at once, slow ones included (a few kilobytes each, and a descriptor); past them the oldest go
  ConnectionCaps caps{.total = 1024, .per_address = 256};
};

// The probes' listener (poet-coordinator --health-address): /healthz alone, on a port of its own, so that the
// status socket's busiest answers (pictures, replays) never stand between an orchestrator and /healthz (one that
// cannot reach it restarts the coordinator), and with caps of its own. A short idle timeout: a probe sends its
// request at once.
StatusServerOptions health_listener_options();

// The descriptors a server started with these options may hold at most: its caps, the connections shed but not yet
// closed, the listening socket and its loops' own.
size_t descriptors_needed(const StatusServerOptions& options);

// Shrinks the caps of the status socket and the probes' listener, both by one factor, until the descriptors they
// may hold fit in half of descriptor_limit (the process's RLIMIT_NOFILE), so that a crowd on them leaves the run the
// other half (ZeroMQ's sockets, one per worker; files; local workers' pipes). Returns true when they were shrunk.
bool fit_listeners(uint64_t descriptor_limit, StatusServerOptions& status, StatusServerOptions& health);

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
