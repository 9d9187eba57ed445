#pragma once
// Loopback TCP ports for the tests: one held for a test (bound, so that nothing else takes it, and listening or
// not), closed with the object; and one free at the time of asking. The one place tests take a port of their own.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>

namespace poet::testing {

class LoopbackPort {
 public:
  // A port the kernel chooses, on 127.0.0.1; port() is -1 when it could not be bound.
  explicit LoopbackPort(bool listening) : fd_(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (fd_ < 0 || ::bind(fd_, reinterpret_cast<sockaddr*>(&address), length) != 0 ||
        (listening && ::listen(fd_, 16) != 0) ||
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) != 0)
      return;
    port_ = ntohs(address.sin_port);
  }
  ~LoopbackPort() {
    if (fd_ >= 0) ::close(fd_);
  }
  LoopbackPort(const LoopbackPort&) = delete;
  LoopbackPort& operator=(const LoopbackPort&) = delete;

  int fd() const { return fd_; }
  int port() const { return port_; }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }  // as poetctl takes it
  std::string endpoint() const { return "tcp://" + address(); }                 // as ZeroMQ takes it

 private:
  int fd_;
  int port_ = -1;
};

// A loopback port free at the time of asking (the kernel's choice), for a process that must come back on the same
// port; -1 when none could be had.
inline int free_port() { return LoopbackPort(false).port(); }

}  // namespace poet::testing
