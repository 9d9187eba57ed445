#include "simulation/envgen/cppn_mutation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "simulation/envgen/cppn_course.h"

namespace poet {
namespace {

// input → hidden (sin) → output, and input → output: three weights and two biases.
CppnGenome parent_genome() {
  CppnGenome g = cppn_seed_genome(-0.4, 0.3);
  g.nodes.push_back({2, CppnRole::kHidden, CppnActivation::kSin, 0.2});
  g.connections.push_back({0, 2, 0.5});
  g.connections.push_back({2, 1, 0.7});
  canonicalize(g);
  return g;
}

double rise(const CppnGenome& g) {
  const std::vector<double> relief = cppn_relief(g);
  return *std::max_element(relief.begin(), relief.end());
}

// Within k standard errors of a proportion p over n draws.
void expect_proportion(double observed, double p, double n, const char* what) {
  const double k = 4.0;
  EXPECT_NEAR(observed, p, k * std::sqrt(p * (1 - p) / n)) << what;
}

TEST(CppnMutation, StatisticsOfTenThousandChildrenMatchTheRates) {
  const CppnGenome parent = parent_genome();
  constexpr int kChildren = 10'000;
  int added = 0, deleted = 0, unchanged_structure = 0;
  int params = 0, perturbed = 0;
  double sum = 0, sum_sq = 0;
  std::map<CppnActivation, int> new_activations;
  for (int i = 0; i < kChildren; ++i) {
    RandomStream stream(stream_key(5, "cppn-mutation-statistics", {static_cast<uint64_t>(i)}));
    CppnStructuralMutation made;
    const CppnGenome child = draw_cppn_child(parent, stream, &made);
    if (made == CppnStructuralMutation::kAddNode) {
      added += 1;
      EXPECT_EQ(child.nodes.size(), parent.nodes.size() + 1);
      EXPECT_EQ(child.connections.size(), parent.connections.size() + 1);  // one split into two
      new_activations[child.nodes.back().activation] += 1;
      EXPECT_EQ(child.nodes.back().id, 3);
      continue;
    }
    if (made == CppnStructuralMutation::kDeleteNode) {
      deleted += 1;
      EXPECT_EQ(child.nodes.size(), 2u);
      EXPECT_EQ(child.connections, std::vector<CppnConnection>({{0, 1, child.connections[0].weight}}));
      continue;
    }
    unchanged_structure += 1;
    ASSERT_EQ(child.nodes.size(), parent.nodes.size());
    ASSERT_EQ(child.connections.size(), parent.connections.size());
    std::vector<std::pair<double, double>> pairs;  // (parent's value, child's)
    for (size_t c = 0; c < parent.connections.size(); ++c)
      pairs.emplace_back(parent.connections[c].weight, child.connections[c].weight);
    for (size_t n = 1; n < parent.nodes.size(); ++n) pairs.emplace_back(parent.nodes[n].bias, child.nodes[n].bias);
    EXPECT_EQ(child.nodes[0].bias, 0.0);  // the input has none
    for (const auto& [before, after] : pairs) {
      params += 1;
      if (after == before) continue;
      perturbed += 1;
      sum += after - before;
      sum_sq += (after - before) * (after - before);
    }
  }
  expect_proportion(added / double(kChildren), kCppnAddNodeProbability, kChildren, "add node");
  expect_proportion(deleted / double(kChildren), kCppnDeleteNodeProbability, kChildren, "delete node");
  expect_proportion(perturbed / double(params), kCppnPerturbProbability, params, "perturbed");
  const double mean = sum / perturbed, sd = std::sqrt(sum_sq / perturbed - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4 * kCppnPerturbStddev / std::sqrt(perturbed));
  EXPECT_NEAR(sd, kCppnPerturbStddev, 4 * kCppnPerturbStddev / std::sqrt(2.0 * perturbed));
  ASSERT_EQ(new_activations.size(), 5u);
  for (const auto& [activation, count] : new_activations)
    expect_proportion(count / double(added), 0.2, added, "activation of a new node");
  EXPECT_EQ(added + deleted + unchanged_structure, kChildren);
}

TEST(CppnMutation, AnAddedNodeSplitsAConnection) {
  const CppnGenome parent = cppn_seed_genome(0.8, 0.0);
  bool split = false;
  for (int i = 0; i < 1000 && !split; ++i) {
    RandomStream stream(stream_key(1, "split", {static_cast<uint64_t>(i)}));
    CppnStructuralMutation made;
    const CppnGenome child = draw_cppn_child(parent, stream, &made);
    if (made != CppnStructuralMutation::kAddNode) continue;
    // the only connection 0 → 1 became 0 → 2 (weight 1) and 2 → 1 (weight 0.8), each perhaps perturbed
    ASSERT_EQ(child.connections.size(), 2u);
    EXPECT_EQ(child.connections[0].from, 0);
    EXPECT_EQ(child.connections[0].to, 2);
    EXPECT_NEAR(child.connections[0].weight, 1.0, 0.6);
    EXPECT_EQ(child.connections[1].from, 2);
    EXPECT_EQ(child.connections[1].to, 1);
    EXPECT_NEAR(child.connections[1].weight, 0.8, 0.6);
    split = true;
  }
  EXPECT_TRUE(split) << "no node added in 1000 draws at probability 0.1";
}

TEST(CppnMutation, ParametersStayClamped) {
  CppnGenome parent = cppn_seed_genome(9.99, -9.99);
  parent.scale = 1e-3;
  for (int i = 0; i < 500; ++i) {
    RandomStream stream(stream_key(2, "clamp", {static_cast<uint64_t>(i)}));
    const CppnGenome child = draw_cppn_child(parent, stream);
    for (const CppnConnection& c : child.connections) EXPECT_LE(std::abs(c.weight), kCppnParamLimit);
    for (const CppnNode& n : child.nodes) EXPECT_LE(std::abs(n.bias), kCppnParamLimit);
  }
}

TEST(CppnMutation, ChildrenDifferHaveAPathAndARiseWithinTheBounds) {
  CppnGenome parent = parent_genome();
  for (int i = 0; i < 300; ++i) {
    RandomStream stream(stream_key(3, "children", {static_cast<uint64_t>(i)}));
    const CppnGenome child = mutate_cppn(parent, stream);
    ASSERT_NE(child, parent);
    ASSERT_FALSE(validate_cppn_course(child)) << *validate_cppn_course(child);
    EXPECT_GE(rise(child), kCppnMinRise - 1e-9);
    EXPECT_LE(rise(child), kCppnMaxRise + 1e-9);
    parent = child;  // a lineage, so structure grows and shrinks
  }
}

TEST(CppnMutation, RiseNormalisation) {
  // a rise of 0.01·(178π/100) ≈ 0.056 m is scaled into [0.25, 0.75]; one of 10·178π/100 ≈ 55.9 m into [12, 16]
  RandomStream stream(9);
  CppnGenome low = cppn_seed_genome(0.01, 0.0);
  ASSERT_TRUE(normalize_cppn_rise(low, stream));
  EXPECT_GE(rise(low), 0.25 - 1e-12);
  EXPECT_LE(rise(low), 0.75 + 1e-12);
  CppnGenome high = cppn_seed_genome(10.0, 0.0);
  ASSERT_TRUE(normalize_cppn_rise(high, stream));
  EXPECT_GE(rise(high), 12 - 1e-9);
  EXPECT_LE(rise(high), 16 + 1e-9);
  CppnGenome middle = cppn_seed_genome(1.0, 0.0);
  const uint64_t before = stream.counter();
  ASSERT_TRUE(normalize_cppn_rise(middle, stream));
  EXPECT_EQ(middle.scale, 1.0);
  EXPECT_EQ(stream.counter(), before);                  // no draw
  CppnGenome descending = cppn_seed_genome(-1.0, 0.0);  // no point above the start pad: redrawn
  EXPECT_FALSE(normalize_cppn_rise(descending, stream));
}

TEST(CppnMutation, AChildIsAFunctionOfParentAndStream) {
  const CppnGenome parent = parent_genome();
  RandomStream a(stream_key(4, "same")), b(stream_key(4, "same"));
  EXPECT_EQ(mutate_cppn(parent, a), mutate_cppn(parent, b));
}

TEST(CppnMutation, FirstGenomeDrawsWeightAndBias) {
  double sum_w2 = 0, sum_b2 = 0;
  constexpr int n = 4000;
  for (int i = 0; i < n; ++i) {
    RandomStream stream(stream_key(6, "first", {static_cast<uint64_t>(i)}));
    const CppnGenome g = first_cppn_genome(stream);
    ASSERT_FALSE(validate(g));
    sum_w2 += g.connections[0].weight * g.connections[0].weight;
    sum_b2 += g.nodes[1].bias * g.nodes[1].bias;
  }
  EXPECT_NEAR(std::sqrt(sum_w2 / n), kCppnSeedWeightStddev, 0.02);
  EXPECT_NEAR(std::sqrt(sum_b2 / n), kCppnBiasStddev, 0.008);
}

}  // namespace
}  // namespace poet
