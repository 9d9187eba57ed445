#pragma once
// The walker's policy (spec §2): a 24 → 40 → 40 → 4 fully connected network with tanh on every layer,
// h ← tanh(h·W + b), in double precision. Parameters are 2804 numbers in the reference's (POET/estool) layout:
// per layer the weight matrix row-major [input][output], then the bias: W1 24×40, b1, W2 40×40, b2, W3 40×4, b3.

#include <Eigen/Core>
#include <array>
#include <span>
#include <vector>

#include "simulation/rng.h"

namespace poet {

inline constexpr int kObsDim = 24;
inline constexpr int kActDim = 4;
inline constexpr int kHidden = 40;
inline constexpr int kParamCount =
    kObsDim * kHidden + kHidden + kHidden * kHidden + kHidden + kHidden * kActDim + kActDim;
static_assert(kParamCount == 2804);

// An immutable network built from a parameter vector. A value type (about 22 KB inline, no heap); act() is const
// and allocation-free, so one Mlp may be shared by threads.
class Mlp {
 public:
  // Throws std::invalid_argument if params does not hold kParamCount finite values (a boundary: params may come
  // from a file or the network).
  explicit Mlp(std::span<const double> params);

  // The action (each component in [-1, 1]) for one observation. Called once per simulation step. tanh is the
  // project's (math/), within 2.3e-16 of std::tanh (absolute): mlp_test checks a naive std::tanh loop agrees within
  // 1e-12.
  std::array<double, kActDim> act(std::span<const double, kObsDim> obs) const;

  // The parameter vector this network was built from, in the layout above.
  std::vector<double> params() const;

 private:
  // Weights stored transposed ([output][input], column-major): the same memory as the reference's row-major
  // [input][output] matrix, whose columns are the contiguous runs act() adds up.
  Eigen::Matrix<double, kHidden, kObsDim> w1t_;
  Eigen::Matrix<double, kHidden, 1> b1_;
  Eigen::Matrix<double, kHidden, kHidden> w2t_;
  Eigen::Matrix<double, kHidden, 1> b2_;
  Eigen::Matrix<double, kActDim, kHidden> w3t_;
  Eigen::Matrix<double, kActDim, 1> b3_;
};

// kParamCount independent N(0, stddev²) draws, in layout order (2·kParamCount draws of the stream).
std::vector<double> random_params(RandomStream& rng, double stddev = 0.1);

// kParamCount zeros: the network that always answers 0.
std::vector<double> zero_params();

}  // namespace poet
