#include "simulation/envgen/cppn_genome.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace poet {
namespace {

// input → hidden(activation, bias hb) → output (bias 0), weights 1 and w_out; plus input → output with w_direct.
CppnGenome one_hidden(CppnActivation activation, double hidden_bias, double w_out, double w_direct) {
  CppnGenome g = cppn_seed_genome(w_direct, 0.0);
  g.nodes.push_back({2, CppnRole::kHidden, activation, hidden_bias});
  g.connections.push_back({0, 2, 1.0});
  g.connections.push_back({2, 1, w_out});
  canonicalize(g);
  return g;
}

double output_at(const CppnGenome& g, double x) { return cppn_outputs(g, std::vector<double>{x}).front(); }

TEST(CppnGenome, SeedGenomeIsALine) {
  const CppnGenome g = cppn_seed_genome(0.5, 0.2);
  EXPECT_FALSE(validate(g));
  EXPECT_DOUBLE_EQ(output_at(g, 0.0), 0.2);
  EXPECT_DOUBLE_EQ(output_at(g, 2.0), 1.2);  // 0.5·2 + 0.2
}

TEST(CppnGenome, ActivationsAreNeatPythons) {
  // sin(5z), sigmoid(5z), tanh(2.5z), each argument clamped to ±60; square and identity plain
  EXPECT_DOUBLE_EQ(activate(CppnActivation::kSin, 0.4), std::sin(2.0));
  EXPECT_DOUBLE_EQ(activate(CppnActivation::kSigmoid, 0.0), 0.5);
  EXPECT_DOUBLE_EQ(activate(CppnActivation::kSigmoid, 0.2), 1.0 / (1.0 + std::exp(-1.0)));
  EXPECT_DOUBLE_EQ(activate(CppnActivation::kTanh, 0.4), std::tanh(1.0));
  EXPECT_DOUBLE_EQ(activate(CppnActivation::kTanh, -100.0), std::tanh(-60.0));
  EXPECT_DOUBLE_EQ(activate(CppnActivation::kSin, 100.0), std::sin(60.0));
  EXPECT_DOUBLE_EQ(activate(CppnActivation::kSquare, -3.0), 9.0);
  EXPECT_DOUBLE_EQ(activate(CppnActivation::kIdentity, -3.0), -3.0);
}

TEST(CppnGenome, OutputsOfHandComputedNetworks) {
  // out = 2·sin(5·(x + 0.1)): at x = 0.3, 2·sin(2)
  const CppnGenome sine = one_hidden(CppnActivation::kSin, 0.1, 2.0, 0.0);
  EXPECT_DOUBLE_EQ(output_at(sine, 0.3), 0.0 * 0.3 + 2.0 * std::sin(2.0));
  // out = x² − x: at x = 2, 2; at x = −1, 2
  const CppnGenome square = one_hidden(CppnActivation::kSquare, 0.0, 1.0, -1.0);
  EXPECT_DOUBLE_EQ(output_at(square, 2.0), 2.0);
  EXPECT_DOUBLE_EQ(output_at(square, -1.0), 2.0);
  // two hidden nodes in a chain: x → h2 = sigmoid(5x) → h3 = tanh(2.5·(3·h2 − 1.5)) → out = −2·h3 + 0.5
  CppnGenome chain = cppn_seed_genome(0.0, 0.5);
  chain.connections.clear();
  chain.nodes.push_back({2, CppnRole::kHidden, CppnActivation::kSigmoid, 0.0});
  chain.nodes.push_back({3, CppnRole::kHidden, CppnActivation::kTanh, -1.5});
  chain.connections = {{0, 2, 1.0}, {2, 3, 3.0}, {3, 1, -2.0}};
  ASSERT_FALSE(validate(chain));
  const double h2 = 1.0 / (1.0 + std::exp(-5.0 * 0.1));
  const double h3 = std::tanh(2.5 * (3.0 * h2 - 1.5));
  EXPECT_DOUBLE_EQ(output_at(chain, 0.1), -2.0 * h3 + 0.5);
  // the scale multiplies the output
  chain.scale = 4.0;
  EXPECT_DOUBLE_EQ(output_at(chain, 0.1), 4.0 * (-2.0 * h3 + 0.5));
}

TEST(CppnGenome, ValidateNamesTheField) {
  const auto error_of = [](const CppnGenome& g) { return validate(g).value_or("valid"); };
  CppnGenome g = one_hidden(CppnActivation::kSin, 0.1, 2.0, 0.5);
  ASSERT_EQ(error_of(g), "valid");

  CppnGenome cycle = g;  // 2 → 3 → 2
  cycle.nodes.push_back({3, CppnRole::kHidden, CppnActivation::kTanh, 0.0});
  cycle.connections.push_back({2, 3, 1.0});
  cycle.connections.push_back({3, 2, 1.0});
  canonicalize(cycle);
  EXPECT_EQ(error_of(cycle), "cppn.connections: they form a cycle");

  CppnGenome dangling = g;
  dangling.connections.push_back({2, 7, 1.0});
  EXPECT_EQ(error_of(dangling), "cppn.connections[3].to: no node 7");

  CppnGenome huge = g;
  huge.connections[0].weight = 1e308;
  EXPECT_EQ(error_of(huge), "cppn.connections[0].weight: must be a finite number within ±10");
  CppnGenome nan = g;
  nan.nodes[2].bias = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(error_of(nan), "cppn.nodes[2].bias: must be a finite number within ±10");

  CppnGenome many = g;
  for (int id = 3; id < 3 + static_cast<int>(kMaxCppnNodes); ++id)
    many.nodes.push_back({id, CppnRole::kHidden, CppnActivation::kSin, 0.0});
  EXPECT_EQ(error_of(many), "cppn.nodes: 259 nodes; at most 256");

  CppnGenome no_path = g;
  no_path.connections = {{0, 2, 1.0}};
  EXPECT_EQ(error_of(no_path), "cppn.connections: no path from the input to the output");

  CppnGenome into_input = g;
  into_input.connections.push_back({2, 0, 1.0});
  canonicalize(into_input);
  EXPECT_EQ(error_of(into_input), "cppn.connections[2].to: nothing connects into the input");

  CppnGenome duplicate = g;
  duplicate.connections.push_back(duplicate.connections.back());
  EXPECT_EQ(error_of(duplicate), "cppn.connections[3]: connections must be unique and ordered by (from, to)");

  CppnGenome output_activation = g;
  output_activation.nodes[1].activation = CppnActivation::kSin;
  EXPECT_EQ(error_of(output_activation), "cppn.nodes[1].activation: the output's is identity");

  CppnGenome scale = g;
  scale.scale = 0;
  EXPECT_EQ(error_of(scale), "cppn.scale: must be a finite number in (0, 1e12]");

  CppnGenome two_inputs = g;
  two_inputs.nodes[2].role = CppnRole::kInput;
  EXPECT_EQ(error_of(two_inputs), "cppn.nodes[2].id: the input is node 0");
}

TEST(CppnGenome, NamesFollowTheGenes) {
  const CppnGenome a = cppn_seed_genome(0.5, 0.2);
  CppnGenome b = a;
  EXPECT_EQ(cppn_name(a), cppn_name(b));
  EXPECT_EQ(cppn_name(a).size(), 13u);  // "cppn-" and 8 hex digits
  b.connections[0].weight = std::nextafter(0.5, 1.0);
  EXPECT_NE(cppn_name(a), cppn_name(b));
}

TEST(CppnGenome, ActivationNamesRoundTrip) {
  for (CppnActivation a : kCppnActivations) EXPECT_EQ(cppn_activation(to_string(a)), a);
  EXPECT_FALSE(cppn_activation("relu"));
}

}  // namespace
}  // namespace poet
