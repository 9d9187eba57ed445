#include "coordinator/status/connection_shedder.h"

#include <algorithm>

namespace poet {

ConnectionShedder::ConnectionShedder(ConnectionCaps caps) : caps_(caps) {
  caps_.total = std::max<size_t>(caps_.total, 1);
  caps_.per_address = std::clamp<size_t>(caps_.per_address, 1, caps_.total);
}

ConnectionShedder::Admission ConnectionShedder::open(const std::string& address) {
  const Id id = next_id_++;
  addresses_.emplace(id, address);
  std::set<Id>& neighbours = by_address_[address];
  neighbours.insert(id);

  // the address's oldest first: a crowd from one address makes room among its own connections
  std::optional<Id> shed;
  if (neighbours.size() > caps_.per_address) {
    shed = *neighbours.begin();
  } else if (addresses_.size() > caps_.total) {
    shed = addresses_.begin()->first;
  }
  // a shed connection no longer counts: its close comes later, from the server's loop
  if (shed) forget(addresses_.find(*shed));
  return {id, shed};
}

void ConnectionShedder::close(Id id) {
  const auto connection = addresses_.find(id);
  if (connection != addresses_.end()) forget(connection);
}

size_t ConnectionShedder::count(const std::string& address) const {
  const auto found = by_address_.find(address);
  return found == by_address_.end() ? 0 : found->second.size();
}

void ConnectionShedder::forget(std::map<Id, std::string>::iterator connection) {
  const auto neighbours = by_address_.find(connection->second);
  neighbours->second.erase(connection->first);
  if (neighbours->second.empty()) by_address_.erase(neighbours);
  addresses_.erase(connection);
}

}  // namespace poet
