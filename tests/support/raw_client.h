#pragma once
// A raw TCP client for the status socket's tests: a connection from a chosen loopback address (Linux routes all of
// 127.0.0.0/8 to lo, so 127.0.0.2, 127.0.0.3, ... are so many clients), bytes sent whole, what comes back within a
// time limit (up to the first whole HTTP response when asked), and a crowd of slowloris clients. The one place tests
// speak raw HTTP.

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace poet::testing {

// A TCP connection from source (an IPv4 address of lo, port chosen by the kernel) to 127.0.0.1:port, or -1.
inline int connect_to(int port, const char* source = "127.0.0.1") {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  sockaddr_in from{};
  from.sin_family = AF_INET;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::inet_pton(AF_INET, source, &from.sin_addr) != 1 ||
      ::bind(fd, reinterpret_cast<sockaddr*>(&from), sizeof from) != 0 ||
      ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

inline bool send_all(int fd, std::string_view data) {
  while (!data.empty()) {
    const ssize_t sent = ::send(fd, data.data(), data.size(), MSG_NOSIGNAL);
    if (sent < 0 && errno == EINTR) continue;
    if (sent <= 0) return false;
    data.remove_prefix(static_cast<size_t>(sent));
  }
  return true;
}

struct Received {
  std::string data;
  bool closed = false;  // the peer closed (or reset) the connection within the time
};

// True when text holds a whole HTTP response: the headers and Content-Length bytes of body.
inline bool whole_response(const std::string& text) {
  const size_t end = text.find("\r\n\r\n");
  if (end == std::string::npos) return false;
  const size_t field = text.find("Content-Length: ");
  if (field == std::string::npos || field > end) return true;
  return text.size() - (end + 4) >= std::stoul(text.substr(field + 16));
}

// What the peer sends until it closes the connection (or, with until_response, until one whole response came),
// for at most `timeout`.
inline Received receive(int fd, std::chrono::milliseconds timeout, bool until_response = false) {
  using Clock = std::chrono::steady_clock;
  Received r;
  const auto deadline = Clock::now() + timeout;
  while (Clock::now() < deadline && !(until_response && whole_response(r.data))) {
    pollfd p{fd, POLLIN, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (::poll(&p, 1, static_cast<int>(std::max<int64_t>(left, 1))) <= 0) continue;
    char buffer[4096];
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n > 0) {
      r.data.append(buffer, static_cast<size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      r.closed = true;
      break;
    }
  }
  return r;
}

// True when the peer has closed (or reset) the connection, looking without waiting or taking a byte.
inline bool closed_by_peer(int fd) {
  pollfd p{fd, POLLIN, 0};
  char byte;
  return ::poll(&p, 1, 0) > 0 && ::recv(fd, &byte, 1, MSG_PEEK | MSG_DONTWAIT) <= 0;
}

// Slowloris clients: each sends a request line, then a header line every 0.2 s (inside the status socket's and the
// probes' listener's idle timeouts) for as long as it exists, never ending its request. They come from 127.0.0.1, or
// spread in turn over `addresses` addresses from 127.0.0.2 on.
class SlowClients {
 public:
  SlowClients(int port, int count, int addresses = 0) {
    for (int i = 0; i < count; ++i) {
      const std::string source = addresses == 0 ? "127.0.0.1" : "127.0.0." + std::to_string(2 + i % addresses);
      fds_.push_back(connect_to(port, source.c_str()));
      if (fds_.back() < 0 || !send_all(fds_.back(), "GET /status HTTP/1.1\r\nHost: x\r\n")) {
        ADD_FAILURE() << "slow client " << i << " from " << source;
        break;
      }
    }
    trickle_ = std::jthread([this](std::stop_token stop) {
      for (int line = 0; !stop.stop_requested(); ++line) {
        for (int fd : fds_) send_all(fd, "X-Slow-" + std::to_string(line) + ": x\r\n");
        // well inside the probes' listener's idle timeout of 1 s also when a loaded machine delays a round over
        // every connection: only shedding closes any
        for (int i = 0; i < 4 && !stop.stop_requested(); ++i)
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    });
  }
  // the trickle stops first, then the connections close
  ~SlowClients() {
    trickle_.request_stop();
    trickle_.join();
    for (int fd : fds_)
      if (fd >= 0) ::close(fd);
  }
  SlowClients(const SlowClients&) = delete;
  SlowClients& operator=(const SlowClients&) = delete;

  int size() const { return static_cast<int>(fds_.size()); }
  // How many of the connections the server has closed so far.
  int closed() const { return static_cast<int>(std::count_if(fds_.begin(), fds_.end(), closed_by_peer)); }

 private:
  std::vector<int> fds_;
  std::jthread trickle_;
};

}  // namespace poet::testing
