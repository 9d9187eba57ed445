#pragma once
// What the tests of the job socket share: a rogue ZeroMQ peer (its sockets, a Hello, the coordinator's answer),
// /metrics read as numbers, and a free loopback port (from tests/support).

#include <httplib.h>

#include <chrono>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <zmq.hpp>

#include "common/program/build_fingerprint.h"
#include "loopback_port.h"
#include "wire.pb.h"

namespace poet::testing {

inline std::string hello(uint32_t version, uint64_t fingerprint) {
  poet::wire::WorkerMessage message;
  poet::wire::Hello& h = *message.mutable_hello();
  h.set_protocol_version(version);
  h.set_fingerprint_digest(fingerprint);
  h.set_arithmetic_digest(poet::arithmetic_digest());  // a peer on this machine computes as the coordinator does
  h.set_fingerprint(std::string(200, 'x'));  // long enough that a cut lands inside it
  h.set_threads(1);
  h.set_name("rogue");
  return message.SerializeAsString();
}

// One DEALER of the rogue peer, with its own identity.
inline zmq::socket_t rogue_socket(zmq::context_t& context, const std::string& endpoint, const std::string& identity) {
  zmq::socket_t socket(context, zmq::socket_type::dealer);
  socket.set(zmq::sockopt::linger, 0);
  socket.set(zmq::sockopt::routing_id, identity);
  socket.connect(endpoint);
  return socket;
}

// The coordinator's answer to the last frame sent (at most 5 s).
inline std::optional<poet::wire::CoordinatorMessage> answer(zmq::socket_t& socket) {
  zmq::pollitem_t item{socket.handle(), 0, ZMQ_POLLIN, 0};
  if (zmq::poll(&item, 1, std::chrono::milliseconds(5000)) <= 0) return std::nullopt;
  zmq::message_t frame;
  if (!socket.recv(frame)) return std::nullopt;
  poet::wire::CoordinatorMessage message;
  if (!message.ParseFromArray(frame.data(), static_cast<int>(frame.size()))) return std::nullopt;
  return message;
}

// /metrics' samples, by name with labels.
inline std::map<std::string, double> metrics(int port) {
  httplib::Client client("127.0.0.1", port);
  client.set_connection_timeout(5);
  client.set_read_timeout(5);
  std::map<std::string, double> out;
  const auto response = client.Get("/metrics");
  if (!response || response->status != 200) return out;
  static const std::regex kSample(R"(^([a-z_]+(\{[^}]*\})?) ([-0-9.e+]+)$)");
  std::istringstream lines(response->body);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, kSample)) out[m[1]] = std::stod(m[3]);
  }
  return out;
}

inline std::string dropped(const std::string& reason) { return "poet_dropped_frames_total{reason=\"" + reason + "\"}"; }

}  // namespace poet::testing
