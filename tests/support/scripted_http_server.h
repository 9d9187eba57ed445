#pragma once
// A hostile HTTP server for the status clients' tests, and the hostile answers they script for it (the unit tests of
// tools/status_client and poetctl's process tests share them): it listens on 127.0.0.1 (a port the kernel chooses) and
// answers every connection, once its request has come, with scripted bytes — in pieces with a pause between them
// (an answer trickled a byte at a time), the last piece repeated (a body streamed without end) — then hangs up.
// One connection at a time, on a thread of its own; the destructor stops it within a pause and closes everything.

#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <stop_token>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "loopback_port.h"

namespace poet::testing {

struct HttpScript {
  std::vector<std::string> pieces;     // sent in order
  std::chrono::milliseconds pause{0};  // between two pieces
  size_t repeat_last = 0;              // the last piece sent this many more times (while the client takes it)
};

// The pieces of an answer a byte each, for a server that trickles.
inline std::vector<std::string> byte_by_byte(const std::string& text) {
  std::vector<std::string> pieces;
  for (char c : text) pieces.emplace_back(1, c);
  return pieces;
}

// A whole HTTP/1.1 answer with its Content-Length.
inline std::string http_answer(const std::string& body, const std::string& content_type = "application/json",
                               const std::string& status = "200 OK") {
  return "HTTP/1.1 " + status + "\r\nContent-Type: " + content_type +
         "\r\nContent-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
}

// An answer that declares a body of 100 GB and sends 64 KB of it, then the same again `repeat` more times
// (while the client takes it): what a client with a size cap refuses at the headers.
inline HttpScript huge_declared_answer(size_t repeat) {
  return HttpScript{{"HTTP/1.1 200 OK\r\nContent-Type: application/json\r\nContent-Length: 100000000000\r\n\r\n",
                     std::string(65536, ' ')},
                    std::chrono::milliseconds{0},
                    repeat};
}

// A small JSON answer a byte each, `pause` apart: every read is on time, the whole answer takes some 106 pauses.
inline HttpScript trickled_answer(std::chrono::milliseconds pause) {
  return HttpScript{byte_by_byte(http_answer(R"({"run_dir": "x"})")), pause};
}

// An answer without a length whose body is 64 KB, then the same again `repeat` more times (while the client takes
// it): what a client with a size cap refuses once the body outgrows it.
inline HttpScript streamed_answer(size_t repeat) {
  return HttpScript{{"HTTP/1.1 200 OK\r\nContent-Type: application/json\r\n\r\n", std::string(65536, ' ')},
                    std::chrono::milliseconds{0},
                    repeat};
}

// Answers that are not well-formed HTTP, each with what a status client says of it (after "malformed").
struct MalformedAnswer {
  std::string script;
  std::string_view said;
};
inline const std::vector<MalformedAnswer> kMalformedAnswers = {
    {std::string("\x00\xffgarbage\r\n\r\n", 13), "no well-formed HTTP status line"},
    {"", "no well-formed HTTP status line"},  // hangs up without a word
    {"HTTP/1.1 200 OK\r\nContent-Length: -1\r\n\r\n{}", "Content-Length \"-1\" is not a number"},
    {"HTTP/1.1 200 OK\r\nContent-Length: 12abc\r\n\r\n{}", "Content-Length \"12abc\" is not a number"},
    {"HTTP/1.1 200 OK\r\nTransfer-Encoding: chunked\r\n\r\nfffffffffffffff\r\n{}", "body is cut short"},
    {"HTTP/1.1 200 OK\r\nContent-Length: 100\r\n\r\n{}", "body is cut short"},
};

class ScriptedHttpServer {
 public:
  explicit ScriptedHttpServer(HttpScript script)
      : port_(true), script_(std::move(script)), thread_([this](std::stop_token stop) { serve(stop); }) {}
  ~ScriptedHttpServer() = default;  // the jthread asks the loop to stop and joins it; the port closes after
  ScriptedHttpServer(const ScriptedHttpServer&) = delete;
  ScriptedHttpServer& operator=(const ScriptedHttpServer&) = delete;

  int port() const { return port_.port(); }
  std::string address() const { return port_.address(); }

 private:
  // Waits at most `ms` for fd to be readable, waking for a stop request every 20 ms.
  static bool readable(int fd, int ms, const std::stop_token& stop) {
    for (int waited = 0; waited < ms && !stop.stop_requested(); waited += 20) {
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 20) > 0) return true;
    }
    return false;
  }

  void serve(const std::stop_token& stop) {
    while (!stop.stop_requested()) {
      if (!readable(port_.fd(), 100, stop)) continue;
      const int client = ::accept4(port_.fd(), nullptr, nullptr, SOCK_CLOEXEC);
      if (client < 0) continue;
      const timeval send_timeout{1, 0};  // a client that stops taking bytes cannot hold the thread
      ::setsockopt(client, SOL_SOCKET, SO_SNDTIMEO, &send_timeout, sizeof send_timeout);
      answer(client, stop);
      ::close(client);
    }
  }

  // Reads the request's head (for at most a second), then sends the script.
  void answer(int client, const std::stop_token& stop) {
    std::string request;
    while (request.find("\r\n\r\n") == std::string::npos && request.size() < 65536 && readable(client, 1000, stop)) {
      char buffer[4096];
      const ssize_t n = ::recv(client, buffer, sizeof buffer, 0);
      if (n <= 0) return;
      request.append(buffer, static_cast<size_t>(n));
    }
    const size_t total = script_.pieces.size() + (script_.pieces.empty() ? 0 : script_.repeat_last);
    for (size_t i = 0; i < total && !stop.stop_requested(); ++i) {
      const std::string& piece = script_.pieces[std::min(i, script_.pieces.size() - 1)];
      if (i > 0 && script_.pause.count() > 0) std::this_thread::sleep_for(script_.pause);
      if (!send_all(client, piece)) return;  // the client gave up
    }
  }

  static bool send_all(int fd, std::string_view data) {
    while (!data.empty()) {
      const ssize_t sent = ::send(fd, data.data(), data.size(), MSG_NOSIGNAL);
      if (sent <= 0) return false;
      data.remove_prefix(static_cast<size_t>(sent));
    }
    return true;
  }

  LoopbackPort port_;
  const HttpScript script_;
  std::jthread thread_;  // last: started once the port and the script exist, joined before they go
};

}  // namespace poet::testing
