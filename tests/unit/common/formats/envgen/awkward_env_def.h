#pragma once
// A definition with every type present and numbers that have no short decimal form, for the round-trip tests of
// every form an environment travels in (JSON, protobuf).

#include <gtest/gtest.h>

#include <cmath>

#include "simulation/envgen/env_encoding.h"

namespace poet::testing {

inline EnvDef awkward_def() {
  EnvDef def;
  def.encoding.name = "awkward";
  def.encoding.roughness = 0.1 + 0.2;
  def.encoding.pit_gap = Interval{1.0 / 3.0, 2.0 / 3.0 + 1.0};
  def.encoding.stump_width = Interval{1.0, 3.0};
  def.encoding.stump_height = Interval{5e-324, 19.999999999999996};
  def.encoding.stump_float = Interval{0.0, 1.0};
  def.encoding.stair_height = Interval{std::nextafter(0.4, 1.0), std::nextafter(0.4, 1.0)};
  def.encoding.stair_width = Interval{4.0, 5.0};
  def.encoding.stair_steps = Interval{1.0, 9.0};
  def.seed = 999'999;
  return def;
}

inline void expect_same(const EnvDef& a, const EnvDef& b) {
  EXPECT_TRUE(a.encoding.same_genes(b.encoding));
  EXPECT_EQ(a.encoding.name, b.encoding.name);
  EXPECT_EQ(a.seed, b.seed);
}

}  // namespace poet::testing
