#include "common/formats/envgen/cppn_json.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string_view>

namespace poet {
namespace {

using nlohmann::json;

constexpr std::string_view kRoles[] = {"input", "output", "hidden"};  // CppnRole's order

std::string item(std::string_view list, size_t i) {
  return "cppn." + std::string(list) + "[" + std::to_string(i) + "]";
}

// The first key of object outside allowed, or of required missing from it, as an error.
std::optional<std::string> check_keys(const json& object, const std::string& where,
                                      std::initializer_list<std::string_view> required,
                                      std::initializer_list<std::string_view> optional = {}) {
  if (!object.is_object()) return where + ": must be an object, got " + object.type_name();
  for (const auto& [key, value] : object.items()) {
    const auto is = [&](std::string_view k) { return k == key; };
    if (std::none_of(required.begin(), required.end(), is) && std::none_of(optional.begin(), optional.end(), is))
      return where + "." + key + ": unknown key";
  }
  for (std::string_view key : required)
    if (!object.contains(std::string(key))) return where + "." + std::string(key) + ": missing";
  return std::nullopt;
}

std::optional<std::string> read_number(const json& j, const std::string& where, double& out) {
  if (!j.is_number()) return where + ": must be a number, got " + j.type_name();
  out = j.get<double>();
  if (!std::isfinite(out)) return where + ": must be a finite number";
  return std::nullopt;
}

std::optional<std::string> read_id(const json& j, const std::string& where, int& out) {
  if (!j.is_number_integer()) return where + ": must be an integer node id";
  const int64_t v = j.get<int64_t>();
  if (v < 0 || v > kMaxCppnNodeId) return where + ": must be in [0, " + std::to_string(kMaxCppnNodeId) + "]";
  out = static_cast<int>(v);
  return std::nullopt;
}

std::optional<std::string> read_node(const json& j, const std::string& where, CppnNode& node) {
  if (auto err = check_keys(j, where, {"id", "role"}, {"activation", "bias"})) return err;
  if (auto err = read_id(j["id"], where + ".id", node.id)) return err;
  const json& role = j["role"];
  const auto r =
      role.is_string() ? std::find(std::begin(kRoles), std::end(kRoles), role.get<std::string>()) : std::end(kRoles);
  if (r == std::end(kRoles)) return where + ".role: must be \"input\", \"output\" or \"hidden\"";
  node.role = static_cast<CppnRole>(r - std::begin(kRoles));
  if (node.role == CppnRole::kInput) {
    if (j.contains("activation") || j.contains("bias")) return where + ": the input has no activation and no bias";
    return std::nullopt;
  }
  if (!j.contains("activation")) return where + ".activation: missing";
  if (!j.contains("bias")) return where + ".bias: missing";
  const json& a = j["activation"];
  const std::optional<CppnActivation> activation = a.is_string() ? cppn_activation(a.get<std::string>()) : std::nullopt;
  if (!activation) return where + ".activation: must be one of identity, sin, sigmoid, square, tanh";
  node.activation = *activation;
  return read_number(j["bias"], where + ".bias", node.bias);
}

std::optional<std::string> read_connection(const json& j, const std::string& where, CppnConnection& c) {
  if (auto err = check_keys(j, where, {"from", "to", "weight"})) return err;
  if (auto err = read_id(j["from"], where + ".from", c.from)) return err;
  if (auto err = read_id(j["to"], where + ".to", c.to)) return err;
  return read_number(j["weight"], where + ".weight", c.weight);
}

}  // namespace

json cppn_to_json(const CppnGenome& genome) {
  json nodes = json::array(), connections = json::array();
  for (const CppnNode& n : genome.nodes) {
    json node = {{"id", n.id}, {"role", kRoles[static_cast<size_t>(n.role)]}};
    if (n.role != CppnRole::kInput) {
      node["activation"] = to_string(n.activation);
      node["bias"] = n.bias;
    }
    nodes.push_back(std::move(node));
  }
  for (const CppnConnection& c : genome.connections)
    connections.push_back({{"from", c.from}, {"to", c.to}, {"weight", c.weight}});
  return {{"nodes", std::move(nodes)}, {"connections", std::move(connections)}, {"scale", genome.scale}};
}

Expected<CppnGenome> cppn_from_json(const json& object) {
  if (auto err = check_keys(object, "cppn", {"nodes", "connections", "scale"})) return Unexpected{*err};
  const json& nodes = object["nodes"];
  const json& connections = object["connections"];
  if (!nodes.is_array()) return Unexpected{std::string("cppn.nodes: must be a list")};
  if (!connections.is_array()) return Unexpected{std::string("cppn.connections: must be a list")};
  if (nodes.size() > kMaxCppnNodes)
    return Unexpected{"cppn.nodes: " + std::to_string(nodes.size()) + " nodes; at most " +
                      std::to_string(kMaxCppnNodes)};
  if (connections.size() > kMaxCppnConnections)
    return Unexpected{"cppn.connections: " + std::to_string(connections.size()) + " connections; at most " +
                      std::to_string(kMaxCppnConnections)};
  CppnGenome genome;
  genome.nodes.resize(nodes.size());
  genome.connections.resize(connections.size());
  for (size_t i = 0; i < nodes.size(); ++i)
    if (auto err = read_node(nodes[i], item("nodes", i), genome.nodes[i])) return Unexpected{*err};
  for (size_t i = 0; i < connections.size(); ++i)
    if (auto err = read_connection(connections[i], item("connections", i), genome.connections[i]))
      return Unexpected{*err};
  if (auto err = read_number(object["scale"], "cppn.scale", genome.scale)) return Unexpected{*err};
  if (auto err = validate(genome)) return Unexpected{*err};
  return genome;
}

}  // namespace poet
