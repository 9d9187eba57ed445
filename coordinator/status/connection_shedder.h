#pragma once
// Which connection a listener closes so that a new client always gets in: when a new connection makes its address
// hold more than per_address, the oldest of that address is shed; else, when the listener holds more than total,
// the oldest of all. Slow clients (a request trickled forever, or nothing sent) are the oldest, since a client
// that sends its request at once is answered within milliseconds, so a crowd under any cap can fill the listener
// and still never keep a probe out. Pure bookkeeping: the server closes what it names. Not thread-safe: the caller
// locks.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>

namespace poet {

struct ConnectionCaps {
  size_t total = 1024;       // connections the listener holds at once, at least 1
  size_t per_address = 256;  // of them from one client address, in [1, total]
};

class ConnectionShedder {
 public:
  using Id = uint64_t;  // from 1, in the order the connections opened; 0 is never one

  struct Admission {
    Id id;                   // the new connection's
    std::optional<Id> shed;  // the connection to close to make room for it
  };

  explicit ConnectionShedder(ConnectionCaps caps);

  // A new connection from address (any text naming the client's address, without its port).
  Admission open(const std::string& address);
  // The connection is gone, closed by either side; an id shed or closed before (or never opened) is ignored.
  void close(Id id);

  size_t size() const { return addresses_.size(); }  // connections held, those shed not counted
  size_t count(const std::string& address) const;    // of them from address

 private:
  void forget(std::map<Id, std::string>::iterator connection);

  ConnectionCaps caps_;
  Id next_id_ = 1;
  std::map<Id, std::string> addresses_;             // each connection held, oldest first, with its address
  std::map<std::string, std::set<Id>> by_address_;  // each address's connections, oldest first
};

}  // namespace poet
