#pragma once
// A self-pipe that wakes a loop blocked in poll() on its read end: other threads call notify() when the loop has
// something new to look at (work to send, a finished job, a stop). notify() is safe from any thread and never
// blocks; the loop drains the pipe after each wake-up.

namespace poet {

class WakePipe {
 public:
  WakePipe();  // throws std::system_error when no pipe can be made
  ~WakePipe();
  WakePipe(const WakePipe&) = delete;
  WakePipe& operator=(const WakePipe&) = delete;

  void notify();
  void drain();  // the loop's side: empties the pipe
  int read_fd() const { return fds_[0]; }

 private:
  int fds_[2] = {-1, -1};
};

}  // namespace poet
