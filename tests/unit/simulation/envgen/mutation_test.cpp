#include "simulation/envgen/mutation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "simulation/envgen/named_courses.h"

namespace poet {
namespace {

std::vector<Interval> iv(std::initializer_list<Interval> list) { return list; }

MutationOptions every_type() {
  MutationOptions o;
  o.stairs = true;
  return o;
}

TEST(MutationRound, MirrorsNumpyRoundingOfTheScaledValue) {
  // numpy: rint(x * 10) / 10, ties to even on the double x * 10
  EXPECT_EQ(round1(0.65), 0.6);  // 6.5 -> 6 (Python's round(0.65, 1) would give 0.7)
  EXPECT_EQ(round1(0.75), 0.8);  // 7.5 -> 8
  EXPECT_EQ(round1(0.25), 0.2);  // 2.5 -> 2
  EXPECT_EQ(round1(0.35), 0.4);  // 0.35 * 10 is exactly 3.5 in doubles -> 4
  EXPECT_EQ(round1(0.1 + 0.2), 0.3);
  EXPECT_EQ(round1(1.2000000000000002), 1.2);
  EXPECT_EQ(round1(-0.04), 0.0);
  EXPECT_TRUE(std::signbit(round1(-0.04)));  // as numpy: -0.0, which mutated_roughness must clear
}

TEST(MutationRoughness, RoundsThenClamps) {
  EXPECT_EQ(mutated_roughness(0.3, 0.26), 0.6);   // 0.56 -> 0.6
  EXPECT_EQ(mutated_roughness(5.0, -0.55), 4.4);  // 4.45 -> 44.5 -> 44 (ties to even)
  EXPECT_EQ(mutated_roughness(2.0, 0.0), 2.0);
  EXPECT_EQ(mutated_roughness(9.8, 0.5), 10.0);            // 10.3 clamped
  EXPECT_EQ(mutated_roughness(10.0, 0.6), 10.0);           // at the maximum
  EXPECT_EQ(mutated_roughness(0.0, -0.3), 0.0);            // clamped at 0
  const double near_zero = mutated_roughness(0.0, -0.04);  // round1 gives -0.0
  EXPECT_EQ(near_zero, 0.0);
  EXPECT_FALSE(std::signbit(near_zero));  // so the name reads "r0.0", never "r-0.0"
}

TEST(MutationLegalMoves, GapFromItsInitialValue) {
  // lo-0.4 is below I.lo = 0 and hi-0.4 below I.hi = 0.8
  EXPECT_EQ(legal_moves({0.0, 0.8}, kPitGapRule), iv({{0.4, 1.2}, {0.4, 0.8}, {0.0, 1.2}}));
}

TEST(MutationLegalMoves, GapAtItsMaximum) {
  // nothing may pass 8; lo' <= hi' still allows the equal interval [7.6, 7.6]
  EXPECT_EQ(legal_moves({8.0, 8.0}, kPitGapRule), iv({{7.6, 8.0}, {7.6, 7.6}}));
}

TEST(MutationLegalMoves, AllEightInTheMiddleInReferenceOrder) {
  EXPECT_EQ(legal_moves({1.0, 2.0}, kStumpHeightRule),
            iv({{1.2, 2.2}, {1.2, 2.0}, {1.2, 1.8}, {1.0, 2.2}, {1.0, 1.8}, {0.8, 2.2}, {0.8, 2.0}, {0.8, 1.8}}));
}

TEST(MutationLegalMoves, EqualBoundsNeverInvert) {
  // [1, 1]: moves that would invert the interval are dropped
  EXPECT_EQ(legal_moves({1.0, 1.0}, kStumpHeightRule),
            iv({{1.2, 1.2}, {1.0, 1.2}, {0.8, 1.2}, {0.8, 1.0}, {0.8, 0.8}}));
}

TEST(MutationLegalMoves, StepCountsKeepOneValue) {
  // lo' + 1 <= hi': [2, 2] and [1, 1] would hold no integer
  EXPECT_EQ(legal_moves({1.0, 2.0}, kStairStepsRule), iv({{2.0, 3.0}, {1.0, 3.0}}));
  EXPECT_EQ(legal_moves({8.0, 9.0}, kStairStepsRule), iv({{7.0, 9.0}, {7.0, 8.0}}));
}

TEST(MutationLegalMoves, RoundsEachValueAndSkipsTheZeroChangeNotTheSameValue) {
  // lo: 0.65 -> 0.6, 0.25 -> 0.2, -0.15 -> -0.2 (illegal); hi: 1.45.. -> 1.5, 1.05 -> 1.0, 0.65 -> 0.6 (illegal).
  // (0.2, 1.0) differs from the parent but is the (0, 0) change, which the reference skips.
  EXPECT_EQ(legal_moves({0.25, 1.05}, kPitGapRule), iv({{0.6, 1.5}, {0.6, 1.0}, {0.2, 1.5}}));
}

TEST(MutationLegalMoves, NoneOutsideTheLegalRegion) {
  EXPECT_TRUE(legal_moves({0.0, 0.2}, kPitGapRule).empty());  // every hi' is below I.hi = 0.8
  EXPECT_TRUE(legal_moves({9.0, 9.5}, kPitGapRule).empty());  // every lo' is above M = 8
}

TEST(MutationInterval, UnchangedAndNoDrawWhenNoMoveIsLegal) {
  RandomStream stream(stream_key(1, "test"));
  EXPECT_EQ(mutate_interval(Interval{9.0, 9.5}, kPitGapRule, stream), (Interval{9.0, 9.5}));
  EXPECT_EQ(stream.counter(), 0u);
}

TEST(MutationInterval, AbsentBecomesInitialWithoutDraw) {
  RandomStream stream(stream_key(1, "test"));
  EXPECT_EQ(mutate_interval(std::nullopt, kPitGapRule, stream), (Interval{0.0, 0.8}));
  EXPECT_EQ(mutate_interval(std::nullopt, kStairStepsRule, stream), (Interval{1.0, 2.0}));
  EXPECT_EQ(stream.counter(), 0u);
}

TEST(MutationInterval, PicksTheDrawnIndexAmongLegalMoves) {
  const std::vector<Interval> moves = legal_moves({0.0, 0.8}, kPitGapRule);
  std::map<double, int> counts;  // by hi + 10·lo, which tells the three moves apart
  for (uint64_t key = 0; key < 3000; ++key) {
    RandomStream stream(stream_key(key, "test"));
    RandomStream twin = stream;
    const Interval got = mutate_interval(Interval{0.0, 0.8}, kPitGapRule, stream);
    EXPECT_EQ(got, moves[static_cast<size_t>(twin.uniform_int(0, 3))]);
    ++counts[got.hi + 10 * got.lo];
  }
  ASSERT_EQ(counts.size(), 3u);
  for (const auto& [move, n] : counts) EXPECT_NEAR(n, 1000, 120) << move;  // about 5 standard deviations
}

TEST(Mutation, FlatGetsEveryEnabledTypeAtItsInitialValuesWithoutDraws) {
  MutationOptions options = every_type();
  options.roughness = false;
  RandomStream stream(stream_key(7, "reproduce"));
  const EnvEncoding child = mutate(EnvEncoding{}, options, stream);
  EXPECT_EQ(stream.counter(), 0u);
  EXPECT_EQ(child.roughness, 0.0);
  EXPECT_EQ(child.pit_gap, (Interval{0.0, 0.8}));
  EXPECT_EQ(child.stump_width, (Interval{1.0, 2.0}));
  EXPECT_EQ(child.stump_height, (Interval{0.0, 0.4}));
  EXPECT_EQ(child.stump_float, (Interval{0.0, 1.0}));
  EXPECT_EQ(child.stair_height, (Interval{0.0, 0.4}));
  EXPECT_EQ(child.stair_width, (Interval{4.0, 5.0}));
  EXPECT_EQ(child.stair_steps, (Interval{1.0, 2.0}));
  EXPECT_EQ(child.name, "r0.0.p0.0_0.8.b1.0_0.0_0.4.s1.0_0.4");
  EXPECT_EQ(validate(child), std::nullopt);
}

TEST(Mutation, ReferenceOptionsOnFlatDrawOnlyTheRoughness) {
  RandomStream stream(stream_key(3, "reproduce", {200}));
  RandomStream twin = stream;
  const EnvEncoding child = mutate(EnvEncoding{}, MutationOptions{}, stream);
  EXPECT_EQ(child.roughness, mutated_roughness(0.0, twin.uniform(-0.6, 0.6)));
  EXPECT_EQ(stream.counter(), twin.counter());  // one draw in all
  EXPECT_EQ(child.pit_gap, (Interval{0.0, 0.8}));
  EXPECT_TRUE(child.has_stumps());
  EXPECT_FALSE(child.has_stairs());  // stairs are off by default
  EXPECT_EQ(child.name, reference_name(child));
}

TEST(Mutation, ExistingStumpsKeepWidthMoveHeightAndResetFloat) {
  EnvEncoding parent = *named_course("hardcore-like");  // stump width [1, 3]
  parent.stump_float = Interval{0.0, 2.0};
  MutationOptions options;
  options.roughness = options.pits = false;
  RandomStream stream(stream_key(11, "test"));
  RandomStream twin = stream;
  const EnvEncoding child = mutate(parent, options, stream);
  EXPECT_EQ(child.stump_width, (Interval{1.0, 3.0}));
  EXPECT_EQ(child.stump_float, (Interval{0.0, 1.0}));
  const std::vector<Interval> moves = legal_moves(*parent.stump_height, kStumpHeightRule);
  EXPECT_EQ(child.stump_height, moves[static_cast<size_t>(twin.uniform_int(0, int64_t(moves.size())))]);
  EXPECT_EQ(child.pit_gap, parent.pit_gap);  // disabled: copied
  EXPECT_EQ(child.roughness, parent.roughness);
}

TEST(Mutation, StairStepsChangeOnlyWithTheOption) {
  EnvEncoding parent;
  parent.stair_height = Interval{0.4, 0.8};
  parent.stair_width = Interval{4.0, 5.0};
  parent.stair_steps = Interval{1.0, 2.0};
  MutationOptions options;
  options.roughness = options.pits = options.stumps = false;
  options.stairs = true;
  bool height_moved = false;
  for (uint64_t key = 0; key < 50; ++key) {
    RandomStream stream(stream_key(key, "test"));
    const EnvEncoding child = mutate(parent, options, stream);
    EXPECT_EQ(child.stair_steps, (Interval{1.0, 2.0}));
    height_moved |= child.stair_height != parent.stair_height;
  }
  EXPECT_TRUE(height_moved);

  options.mutate_stair_steps = true;
  for (uint64_t key = 0; key < 50; ++key) {
    RandomStream stream(stream_key(key, "test"));
    const EnvEncoding child = mutate(parent, options, stream);
    EXPECT_TRUE(child.stair_steps == (Interval{2.0, 3.0}) || child.stair_steps == (Interval{1.0, 3.0}));
    EXPECT_NE(child.stair_height, parent.stair_height);  // [0.4, 0.8] always has a legal move
  }
}

TEST(Mutation, SameStreamKeySameChild) {
  const EnvEncoding parent = *named_course("hard");
  for (uint64_t key = 0; key < 100; ++key) {
    RandomStream a(stream_key(key, "reproduce", {1, 2}));
    RandomStream b(stream_key(key, "reproduce", {1, 2}));
    const EnvEncoding ca = mutate(parent, every_type(), a);
    const EnvEncoding cb = mutate(parent, every_type(), b);
    EXPECT_TRUE(ca.same_genes(cb));
    EXPECT_EQ(ca.name, cb.name);
  }
  int differ = 0;
  for (uint64_t key = 0; key < 100; ++key) {
    RandomStream a(stream_key(key, "reproduce"));
    RandomStream b(stream_key(key + 1000, "reproduce"));
    differ += mutate(parent, every_type(), a).same_genes(mutate(parent, every_type(), b)) ? 0 : 1;
  }
  EXPECT_GT(differ, 80);
}

TEST(Mutation, RoughnessClampedAtZeroAndTen) {
  EnvEncoding low;
  EnvEncoding high;
  high.roughness = 10.0;
  MutationOptions options;
  options.pits = options.stumps = false;
  int at_zero = 0;
  int at_ten = 0;
  for (uint64_t key = 0; key < 1000; ++key) {
    RandomStream a(stream_key(key, "test"));
    RandomStream b(stream_key(key, "test"));
    const double r_low = mutate(low, options, a).roughness;
    const double r_high = mutate(high, options, b).roughness;
    EXPECT_GE(r_low, 0.0);
    EXPECT_FALSE(std::signbit(r_low));
    EXPECT_LE(r_low, 0.6);
    EXPECT_LE(r_high, 10.0);
    EXPECT_GE(r_high, 9.4);
    at_zero += r_low == 0.0 ? 1 : 0;
    at_ten += r_high == 10.0 ? 1 : 0;
  }
  // about 54% of draws (u < 0.05) land on the clamp
  EXPECT_GT(at_zero, 400);
  EXPECT_GT(at_ten, 400);
}

TEST(Mutation, SomeTypesModeMutatesEachTypeAboutHalfTheTime) {
  MutationOptions options = every_type();
  options.all_types = false;
  int pits = 0;
  int stumps = 0;
  int stairs = 0;
  int unchanged = 0;
  for (uint64_t key = 0; key < 4000; ++key) {
    RandomStream stream(stream_key(key, "test"));
    const EnvEncoding child = mutate(EnvEncoding{}, options, stream);
    pits += child.has_pits() ? 1 : 0;
    stumps += child.has_stumps() ? 1 : 0;
    stairs += child.has_stairs() ? 1 : 0;
    unchanged += child.same_genes(EnvEncoding{}) ? 1 : 0;
  }
  EXPECT_NEAR(pits, 2000, 160);
  EXPECT_NEAR(stumps, 2000, 160);
  EXPECT_NEAR(stairs, 2000, 160);
  EXPECT_GT(unchanged, 0);  // possible in this mode (no type chosen, or roughness rounded back to 0)
}

TEST(Mutation, MutateDefDrawsTheSeedAfterTheGenes) {
  const EnvDef parent{*named_course("r1"), 42};
  RandomStream stream(stream_key(5, "reproduce", {400}));
  RandomStream twin = stream;
  const EnvDef child = mutate_def(parent, MutationOptions{}, stream);
  const EnvEncoding genes = mutate(parent.encoding, MutationOptions{}, twin);
  EXPECT_TRUE(child.encoding.same_genes(genes));
  EXPECT_EQ(child.seed, static_cast<uint32_t>(twin.uniform_int(0, kMaxEnvSeed)));
  EXPECT_LT(child.seed, kMaxEnvSeed);
}

bool on_grid(double x) { return round1(x) == x; }

// 10,000 chains of 20 generations, options varied by chain: every child is valid, inside the mutation maxima,
// on the 0.1 grid, and its intervals ordered.
TEST(Mutation, RandomChainsNeverLeaveTheBounds) {
  for (uint64_t chain = 0; chain < 10000; ++chain) {
    MutationOptions options = every_type();
    options.all_types = chain % 2 == 0;
    options.mutate_stair_steps = chain % 3 == 0;
    EnvEncoding e;
    for (uint64_t generation = 0; generation < 20; ++generation) {
      RandomStream stream(stream_key(chain, "chain", {generation}));
      e = mutate(e, options, stream);
      ASSERT_EQ(validate(e), std::nullopt) << e.name;
      ASSERT_EQ(e.name, reference_name(e));
      ASSERT_TRUE(e.roughness >= 0.0 && e.roughness <= 10.0 && on_grid(e.roughness)) << e.name;
      if (e.pit_gap) {
        ASSERT_TRUE(e.pit_gap->lo >= 0.0 && e.pit_gap->hi >= 0.8 && e.pit_gap->hi <= 8.0) << e.name;
        ASSERT_TRUE(e.pit_gap->lo <= e.pit_gap->hi && on_grid(e.pit_gap->lo) && on_grid(e.pit_gap->hi)) << e.name;
      }
      if (e.stump_height) {
        ASSERT_EQ(e.stump_width, (Interval{1.0, 2.0}));
        ASSERT_EQ(e.stump_float, (Interval{0.0, 1.0}));
        const Interval h = *e.stump_height;
        ASSERT_TRUE(h.lo >= 0.0 && h.hi >= 0.4 && h.hi <= 5.0 && h.lo <= h.hi) << e.name;
        ASSERT_TRUE(on_grid(h.lo) && on_grid(h.hi)) << e.name;
      }
      if (e.stair_height) {
        ASSERT_EQ(e.stair_width, (Interval{4.0, 5.0}));
        const Interval h = *e.stair_height;
        ASSERT_TRUE(h.lo >= 0.0 && h.hi >= 0.4 && h.hi <= 5.0 && h.lo <= h.hi) << e.name;
        const Interval s = *e.stair_steps;
        ASSERT_TRUE(s.lo >= 1.0 && s.hi >= 2.0 && s.hi <= 9.0 && s.lo + 1.0 <= s.hi) << e.name;
        ASSERT_TRUE(s.lo == std::floor(s.lo) && s.hi == std::floor(s.hi)) << e.name;
        if (!options.mutate_stair_steps) {
          ASSERT_EQ(s, (Interval{1.0, 2.0}));
        }
      }
    }
  }
}

}  // namespace
}  // namespace poet
