#pragma once
// Enhanced POET's terrain genome (Wang et al. 2020): a NEAT-style compositional pattern-producing network with one
// input (x) and one output (height), hidden nodes with activations, weighted connections and biases. A genome is
// kept canonical — nodes sorted by id, connections by (from, to) — so equal genes compare equal.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace poet {

// neat-python's definitions, which the authors' terrains were drawn with: sigmoid, tanh and sin scale their
// argument (by 5, 2.5 and 5) and clamp it to [−60, 60].
enum class CppnActivation { kIdentity, kSin, kSigmoid, kSquare, kTanh };
inline constexpr CppnActivation kCppnActivations[] = {CppnActivation::kIdentity, CppnActivation::kSin,
                                                      CppnActivation::kSigmoid, CppnActivation::kSquare,
                                                      CppnActivation::kTanh};
enum class CppnRole { kInput, kOutput, kHidden };

struct CppnNode {
  int id = 0;
  CppnRole role = CppnRole::kHidden;
  CppnActivation activation = CppnActivation::kIdentity;  // the input's is unused; the output's is identity
  double bias = 0;                                        // the input's is unused (0)
  friend bool operator==(const CppnNode&, const CppnNode&) = default;
};

struct CppnConnection {
  int from = 0;
  int to = 0;
  double weight = 0;
  friend bool operator==(const CppnConnection&, const CppnConnection&) = default;
};

inline constexpr int kCppnInputId = 0;
inline constexpr int kCppnOutputId = 1;

struct CppnGenome {
  std::vector<CppnNode> nodes;              // by id; the input is kCppnInputId, the output kCppnOutputId
  std::vector<CppnConnection> connections;  // by (from, to)
  // The network's output is multiplied by this: mutation's normalisation of the course's height range.
  double scale = 1;
  friend bool operator==(const CppnGenome&, const CppnGenome&) = default;
};

// Bounds a genome must keep. Mutation clamps weights and biases to ±kCppnParamLimit; the size limits are far
// above anything mutation grows in a run and keep a hostile file from costing more than a course is worth.
inline constexpr double kCppnParamLimit = 10.0;
inline constexpr size_t kMaxCppnNodes = 256;
inline constexpr size_t kMaxCppnConnections = 1024;
inline constexpr int kMaxCppnNodeId = 1'000'000;
inline constexpr double kMaxCppnScale = 1e12;

// "identity", "sin", "sigmoid", "square", "tanh"; and back (nullopt for anything else).
std::string_view to_string(CppnActivation activation);
std::optional<CppnActivation> cppn_activation(std::string_view name);

double activate(CppnActivation activation, double z);

// Sorts nodes and connections into the canonical order.
void canonicalize(CppnGenome& genome);

// Checks a genome's structure and numbers: the sizes, one input and one output (identity), unique ids, biases and
// weights finite within ±kCppnParamLimit, connections between existing nodes, none into the input, no duplicate,
// no cycle, a path from the input to the output, scale finite in (0, kMaxCppnScale], canonical order. Returns a
// message naming the first bad field ("cppn.connections[3].to: ..."), or nothing when valid.
std::optional<std::string> validate(const CppnGenome& genome);

// The network's output (times scale) at each x, for a valid genome; nodes without a path from the input count
// their bias alone. Results may be non-finite when the network overflows.
std::vector<double> cppn_outputs(const CppnGenome& genome, std::span<const double> xs);

// Whether the output can be reached from the input through connections.
bool has_input_output_path(const CppnGenome& genome);

// The first genome of a lineage: input → output with weight w and output bias b.
CppnGenome cppn_seed_genome(double weight, double bias);

// A short label naming the genome by a hash of its genes: "cppn-<8 hex digits>".
std::string cppn_name(const CppnGenome& genome);

}  // namespace poet
