#include "simulation/envgen/cppn_genome.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "math/exponential.h"
#include "math/trigonometry.h"

namespace poet {
namespace {

std::string at(std::string_view list, size_t i) { return "cppn." + std::string(list) + "[" + std::to_string(i) + "]"; }

bool in_limit(double v) { return std::isfinite(v) && std::abs(v) <= kCppnParamLimit; }

// Node positions in evaluation order (every connection's source before its target), or nullopt on a cycle.
// Kahn's algorithm, taking the lowest ready position first so the order is a function of the genome.
std::optional<std::vector<size_t>> topological_order(const CppnGenome& g, const std::map<int, size_t>& index) {
  const size_t n = g.nodes.size();
  std::vector<int> indegree(n, 0);
  std::vector<std::vector<size_t>> out(n);
  for (const CppnConnection& c : g.connections) {
    out[index.at(c.from)].push_back(index.at(c.to));
    indegree[index.at(c.to)] += 1;
  }
  std::set<size_t> ready;
  for (size_t i = 0; i < n; ++i)
    if (indegree[i] == 0) ready.insert(i);
  std::vector<size_t> order;
  while (!ready.empty()) {
    const size_t i = *ready.begin();
    ready.erase(ready.begin());
    order.push_back(i);
    for (size_t j : out[i])
      if (--indegree[j] == 0) ready.insert(j);
  }
  if (order.size() != n) return std::nullopt;
  return order;
}

std::map<int, size_t> node_index(const CppnGenome& g) {
  std::map<int, size_t> index;
  for (size_t i = 0; i < g.nodes.size(); ++i) index.emplace(g.nodes[i].id, i);
  return index;
}

}  // namespace

std::string_view to_string(CppnActivation a) {
  switch (a) {
    case CppnActivation::kIdentity:
      return "identity";
    case CppnActivation::kSin:
      return "sin";
    case CppnActivation::kSigmoid:
      return "sigmoid";
    case CppnActivation::kSquare:
      return "square";
    case CppnActivation::kTanh:
      return "tanh";
  }
  return "identity";
}

std::optional<CppnActivation> cppn_activation(std::string_view name) {
  for (CppnActivation a : kCppnActivations)
    if (to_string(a) == name) return a;
  return std::nullopt;
}

double activate(CppnActivation a, double z) {
  const auto clamp60 = [](double v) { return std::clamp(v, -60.0, 60.0); };
  switch (a) {
    case CppnActivation::kIdentity:
      return z;
    case CppnActivation::kSin:
      return math::sin(clamp60(5.0 * z));
    case CppnActivation::kSigmoid:
      return 1.0 / (1.0 + math::exp(-clamp60(5.0 * z)));
    case CppnActivation::kSquare:
      return z * z;
    case CppnActivation::kTanh:
      return math::tanh(clamp60(2.5 * z));
  }
  return z;
}

void canonicalize(CppnGenome& g) {
  std::sort(g.nodes.begin(), g.nodes.end(), [](const CppnNode& a, const CppnNode& b) { return a.id < b.id; });
  std::sort(g.connections.begin(), g.connections.end(), [](const CppnConnection& a, const CppnConnection& b) {
    return std::pair(a.from, a.to) < std::pair(b.from, b.to);
  });
}

std::optional<std::string> validate(const CppnGenome& g) {
  if (g.nodes.size() > kMaxCppnNodes)
    return "cppn.nodes: " + std::to_string(g.nodes.size()) + " nodes; at most " + std::to_string(kMaxCppnNodes);
  if (g.connections.size() > kMaxCppnConnections)
    return "cppn.connections: " + std::to_string(g.connections.size()) + " connections; at most " +
           std::to_string(kMaxCppnConnections);
  if (!std::isfinite(g.scale) || g.scale <= 0 || g.scale > kMaxCppnScale)
    return "cppn.scale: must be a finite number in (0, 1e12]";
  int inputs = 0, outputs = 0;
  for (size_t i = 0; i < g.nodes.size(); ++i) {
    const CppnNode& n = g.nodes[i];
    if (n.id < 0 || n.id > kMaxCppnNodeId) return at("nodes", i) + ".id: must be in [0, 1000000]";
    if (i > 0 && g.nodes[i - 1].id >= n.id) return at("nodes", i) + ".id: ids must be unique and in ascending order";
    if (!in_limit(n.bias)) return at("nodes", i) + ".bias: must be a finite number within ±10";
    if (n.role == CppnRole::kInput) {
      inputs += 1;
      if (n.id != kCppnInputId) return at("nodes", i) + ".id: the input is node 0";
      if (n.bias != 0 || n.activation != CppnActivation::kIdentity)
        return at("nodes", i) + ": the input has no bias and no activation";
    } else if (n.role == CppnRole::kOutput) {
      outputs += 1;
      if (n.id != kCppnOutputId) return at("nodes", i) + ".id: the output is node 1";
      if (n.activation != CppnActivation::kIdentity) return at("nodes", i) + ".activation: the output's is identity";
    } else if (n.id == kCppnInputId || n.id == kCppnOutputId) {
      return at("nodes", i) + ".id: ids 0 and 1 are the input and the output";
    }
  }
  if (inputs != 1 || outputs != 1) return std::string("cppn.nodes: needs exactly one input (0) and one output (1)");
  const std::map<int, size_t> index = node_index(g);
  for (size_t i = 0; i < g.connections.size(); ++i) {
    const CppnConnection& c = g.connections[i];
    if (!index.contains(c.from)) return at("connections", i) + ".from: no node " + std::to_string(c.from);
    if (!index.contains(c.to)) return at("connections", i) + ".to: no node " + std::to_string(c.to);
    if (c.to == kCppnInputId) return at("connections", i) + ".to: nothing connects into the input";
    if (c.from == c.to) return at("connections", i) + ": a node connects to itself";
    if (!in_limit(c.weight)) return at("connections", i) + ".weight: must be a finite number within ±10";
    if (i > 0 && std::pair(g.connections[i - 1].from, g.connections[i - 1].to) >= std::pair(c.from, c.to))
      return at("connections", i) + ": connections must be unique and ordered by (from, to)";
  }
  if (!topological_order(g, index)) return std::string("cppn.connections: they form a cycle");
  if (!has_input_output_path(g)) return std::string("cppn.connections: no path from the input to the output");
  return std::nullopt;
}

bool has_input_output_path(const CppnGenome& g) {
  std::set<int> reached = {kCppnInputId};
  for (bool grew = true; grew;) {  // a genome is small: relax until nothing new is reached
    grew = false;
    for (const CppnConnection& c : g.connections)
      if (reached.contains(c.from) && reached.insert(c.to).second) grew = true;
  }
  return reached.contains(kCppnOutputId);
}

std::vector<double> cppn_outputs(const CppnGenome& g, std::span<const double> xs) {
  const std::map<int, size_t> index = node_index(g);
  const std::vector<size_t> order = topological_order(g, index).value();
  std::vector<std::vector<std::pair<size_t, double>>> inputs(g.nodes.size());
  for (const CppnConnection& c : g.connections) inputs[index.at(c.to)].emplace_back(index.at(c.from), c.weight);
  const size_t output = index.at(kCppnOutputId);
  std::vector<double> value(g.nodes.size()), out;
  out.reserve(xs.size());
  for (double x : xs) {
    for (size_t i : order) {
      const CppnNode& node = g.nodes[i];
      if (node.role == CppnRole::kInput) {
        value[i] = x;
        continue;
      }
      double z = node.bias;
      for (const auto& [from, weight] : inputs[i]) z += weight * value[from];
      value[i] = activate(node.activation, z);
    }
    out.push_back(value[output] * g.scale);
  }
  return out;
}

CppnGenome cppn_seed_genome(double weight, double bias) {
  CppnGenome g;
  g.nodes = {{kCppnInputId, CppnRole::kInput, CppnActivation::kIdentity, 0.0},
             {kCppnOutputId, CppnRole::kOutput, CppnActivation::kIdentity, bias}};
  g.connections = {{kCppnInputId, kCppnOutputId, weight}};
  return g;
}

std::string cppn_name(const CppnGenome& g) {
  uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a over the genes' bits
  const auto mix = [&](uint64_t v) {
    for (int b = 0; b < 8; ++b) h = (h ^ ((v >> (8 * b)) & 0xff)) * 0x100000001b3ULL;
  };
  for (const CppnNode& n : g.nodes) {
    mix(static_cast<uint64_t>(n.id));
    mix(static_cast<uint64_t>(n.role));
    mix(static_cast<uint64_t>(n.activation));
    mix(std::bit_cast<uint64_t>(n.bias));
  }
  for (const CppnConnection& c : g.connections) {
    mix(static_cast<uint64_t>(c.from));
    mix(static_cast<uint64_t>(c.to));
    mix(std::bit_cast<uint64_t>(c.weight));
  }
  mix(std::bit_cast<uint64_t>(g.scale));
  char buf[16];
  std::snprintf(buf, sizeof buf, "%08x", static_cast<unsigned>(h ^ (h >> 32)));
  return "cppn-" + std::string(buf);
}

}  // namespace poet
