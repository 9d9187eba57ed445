#include "common/plumbing/wake_pipe.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace poet {

WakePipe::WakePipe() {
  if (::pipe2(fds_, O_NONBLOCK | O_CLOEXEC) != 0) throw std::system_error(errno, std::generic_category(), "pipe2");
}

WakePipe::~WakePipe() {
  ::close(fds_[0]);
  ::close(fds_[1]);
}

void WakePipe::notify() {
  const char byte = 1;
  // a full pipe already holds a wake-up: EAGAIN is fine
  [[maybe_unused]] const ssize_t written = ::write(fds_[1], &byte, 1);
}

void WakePipe::drain() {
  char buffer[256];
  while (::read(fds_[0], buffer, sizeof buffer) > 0) {
  }
}

}  // namespace poet
