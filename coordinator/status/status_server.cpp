#include "status/status_server.h"

#include <httplib.h>
#include <pthread.h>
#include <sys/socket.h>

#include <algorithm>
#include <charconv>
#include <condition_variable>
#include <csignal>
#include <mutex>
#include <thread>

#include "status/status_routes.h"
#include "utf8.h"

namespace poet {
namespace {

using namespace std::chrono_literals;

constexpr auto kStartTimeout = 5s;  // from the thread's start to the server accepting

const char* reason_phrase(int status) {
  switch (status) {
    case 400:
      return "bad request";
    case 404:
      return "not found";
    case 405:
      return "method not allowed";
    case 408:
      return "request timeout";
    case 413:
      return "request body too large";
    case 414:
      return "request URI too long";
    case 416:
      return "range not satisfiable";
    case 500:
      return "internal error";
    case 503:
      return "unavailable";
    default:
      return status < 500 ? "client error" : "server error";
  }
}

// httplib's timeouts are (seconds, microseconds).
std::pair<time_t, time_t> split(std::chrono::milliseconds timeout) {
  const auto ms = std::max<int64_t>(timeout.count(), 1);
  return {static_cast<time_t>(ms / 1000), static_cast<time_t>(ms % 1000 * 1000)};
}

}  // namespace

struct StatusServer::Impl {
  httplib::Server server;
  std::thread thread;
  std::mutex mutex;
  std::condition_variable changed;
  bool listen_returned = false;  // under mutex
};

StatusServerOptions health_listener_options() {
  StatusServerOptions options;
  options.threads = 2;  // a probe, and one straggler
  options.read_timeout = 1s;
  options.write_timeout = 1s;
  options.keep_alive_seconds = 1;
  options.health_only = true;
  return options;
}

StatusServer::StatusServer(StatusBoard& board, StatusServerOptions options) : board_(board), options_(options) {}

StatusServer::~StatusServer() { stop(); }

Expected<int> StatusServer::start(const std::string& address) {
  if (impl_) return Unexpected{"status socket: already serving on port " + std::to_string(port_)};
  const Expected<HostPort> where = parse_host_port(address);
  if (!where) return Unexpected{"status socket: " + where.error()};

  auto impl = std::make_unique<Impl>();
  httplib::Server& server = impl->server;
  const size_t threads = static_cast<size_t>(std::clamp(options_.threads, 1, 16));
  server.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  const auto [read_s, read_us] = split(options_.read_timeout);
  const auto [write_s, write_us] = split(options_.write_timeout);
  server.set_read_timeout(read_s, read_us);
  server.set_write_timeout(write_s, write_us);
  server.set_keep_alive_timeout(std::max(options_.keep_alive_seconds, 1));
  server.set_keep_alive_max_count(std::max<size_t>(options_.keep_alive_max_requests, 1));
  server.set_payload_max_length(options_.payload_max_bytes);
  // a response leaves in two writes (headers, body): with Nagle the second waits for the client's delayed ACK,
  // 40 ms on Linux, on every request of a kept-alive connection after the first
  server.set_tcp_nodelay(true);
  server.set_default_headers({{"Cache-Control", "no-store"}});
  // SO_REUSEADDR (a restart may bind while old connections linger) but not httplib's default SO_REUSEPORT, with
  // which a second coordinator could bind the same port and silently share its connections
  server.set_socket_options([](int socket) {
    const int yes = 1;
    ::setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });

  // every request goes to status_response; httplib reads a request's body (up to the limit) before routing it
  StatusBoard& board = board_;
  auto answer = [&board, health_only = options_.health_only](const httplib::Request& request,
                                                             httplib::Response& response) {
    const StatusResponse r = health_only && request.path != "/healthz"
                                 ? error_response(404,
                                                  "this listener answers /healthz only; the rest is on the "
                                                  "status socket (--status-address)")
                                 : status_response(board, request.method, request.path, request.params);
    response.status = r.status;
    if (!r.allow.empty()) response.set_header("Allow", r.allow);
    response.set_content(r.body, r.content_type);
  };
  constexpr char kAnyPath[] = ".*";
  server.Get(kAnyPath, answer);
  server.Post(kAnyPath, answer);
  server.Put(kAnyPath, answer);
  server.Patch(kAnyPath, answer);
  server.Delete(kAnyPath, answer);
  server.Options(kAnyPath, answer);
  // Answered before httplib reads a body: a request that has none (no Content-Length, no Transfer-Encoding), which
  // httplib 0.11 would otherwise read to the end of the connection for POST, PUT, PATCH and DELETE (and answer 400);
  // and the methods it has no handler table for (CONNECT, TRACE, PRI), which would be a bare 400.
  server.set_pre_routing_handler([answer](const httplib::Request& request, httplib::Response& response) {
    const bool has_body = request.has_header("Content-Length") || request.has_header("Transfer-Encoding");
    const bool no_table = request.method == "CONNECT" || request.method == "TRACE" || request.method == "PRI";
    if (request.method == "GET" || request.method == "HEAD" || (has_body && !no_table))
      return httplib::Server::HandlerResponse::Unhandled;
    answer(request, response);
    return httplib::Server::HandlerResponse::Handled;
  });
  // httplib's own errors (a malformed request, a body or URI too long) get the same JSON body as ours
  server.set_error_handler([](const httplib::Request&, httplib::Response& response) {
    if (!response.body.empty()) return;
    const StatusResponse r = error_response(response.status, reason_phrase(response.status));
    response.set_content(r.body, r.content_type);
  });
  server.set_exception_handler([](const httplib::Request&, httplib::Response& response, std::exception_ptr) {
    const StatusResponse r = error_response(500, "internal error");
    response.status = r.status;
    response.set_content(r.body, r.content_type);
  });

  // bind here, so that the error comes back to the caller
  int port = -1;
  if (where->port == 0) {
    port = server.bind_to_any_port(where->host);
  } else if (server.bind_to_port(where->host, where->port)) {
    port = where->port;
  }
  if (port <= 0)
    return Unexpected{"status socket " + valid_utf8(address) +
                      ": cannot listen (the port is in use, or the host is not an address of this machine)"};

  Impl* raw = impl.get();
  raw->thread = std::thread([raw] {
    // a client that hangs up mid-answer must not raise SIGPIPE in the process; the pool's threads, created by
    // listen_after_bind on this thread, inherit the mask
    sigset_t pipe;
    sigemptyset(&pipe);
    sigaddset(&pipe, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe, nullptr);
    raw->server.listen_after_bind();
    std::lock_guard lock(raw->mutex);
    raw->listen_returned = true;
    raw->changed.notify_all();
  });
  impl_ = std::move(impl);
  port_ = port;

  // return once it accepts, so that stop() finds it running
  const auto deadline = std::chrono::steady_clock::now() + kStartTimeout;
  std::unique_lock lock(raw->mutex);
  while (!raw->server.is_running() && !raw->listen_returned && std::chrono::steady_clock::now() < deadline)
    raw->changed.wait_for(lock, 1ms);  // is_running() is not signalled: poll it
  const bool up = raw->server.is_running() && !raw->listen_returned;
  lock.unlock();
  if (!up) {
    stop();
    return Unexpected{"status socket " + valid_utf8(address) + ": the server did not start"};
  }
  return port;
}

void StatusServer::stop() {
  if (!impl_) return;
  Impl& impl = *impl_;
  {
    // httplib's stop() acts only on a running server, and must be called once: wait for it to run (start did),
    // stop it, then wait for the listening thread to finish the requests in hand
    std::unique_lock lock(impl.mutex);
    bool stopped = false;
    while (!impl.listen_returned) {
      if (!stopped && impl.server.is_running()) {
        impl.server.stop();
        stopped = true;
      }
      impl.changed.wait_for(lock, 10ms);
    }
  }
  impl.thread.join();
  impl_.reset();
  port_ = 0;
}

}  // namespace poet
