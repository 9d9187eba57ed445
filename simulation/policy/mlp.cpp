#include "simulation/policy/mlp.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "math/exponential.h"

namespace poet {
namespace {

// Copies the next rows·cols values of params into m. Eigen's default column-major order for an [out][in] matrix
// is exactly the row-major [in][out] order of the file, so this is a plain copy.
template <typename Matrix>
void take(std::span<const double> params, size_t& offset, Matrix& m) {
  const size_t n = static_cast<size_t>(m.size());
  std::copy(params.begin() + offset, params.begin() + offset + n, m.data());
  offset += n;
}

template <typename Matrix>
void put(const Matrix& m, std::vector<double>& out) {
  out.insert(out.end(), m.data(), m.data() + m.size());
}

// out = b + W·x, accumulated column by column (out += W[:, i]·x[i] for i in order): each element is a chain of
// separate products and sums in a fixed order, so vector units of any width give the same bits. (Eigen's own
// matrix–vector kernel fuses multiply–adds where the processor has them — arm64 always does.)
template <typename Out, typename Matrix, typename In>
void affine(const Matrix& w, const In& x, Out& out) {
  for (int i = 0; i < w.cols(); ++i) out.noalias() += w.col(i) * x[i];
}

template <typename Vector>
void tanh_in_place(Vector& v) {
  for (int i = 0; i < v.size(); ++i) v[i] = math::tanh(v[i]);
}

}  // namespace

Mlp::Mlp(std::span<const double> params) {
  if (params.size() != static_cast<size_t>(kParamCount)) {
    throw std::invalid_argument("Mlp: expected " + std::to_string(kParamCount) + " parameters, got " +
                                std::to_string(params.size()));
  }
  for (size_t i = 0; i < params.size(); ++i) {
    if (!std::isfinite(params[i])) {
      throw std::invalid_argument("Mlp: parameter " + std::to_string(i) + " is not finite");
    }
  }
  size_t offset = 0;
  take(params, offset, w1t_);
  take(params, offset, b1_);
  take(params, offset, w2t_);
  take(params, offset, b2_);
  take(params, offset, w3t_);
  take(params, offset, b3_);
}

std::array<double, kActDim> Mlp::act(std::span<const double, kObsDim> obs) const {
  const Eigen::Map<const Eigen::Matrix<double, kObsDim, 1>> x(obs.data());
  // fixed-size temporaries live on the stack: no heap allocation per call
  Eigen::Matrix<double, kHidden, 1> h1 = b1_;
  affine(w1t_, x, h1);
  tanh_in_place(h1);
  Eigen::Matrix<double, kHidden, 1> h2 = b2_;
  affine(w2t_, h1, h2);
  tanh_in_place(h2);
  Eigen::Matrix<double, kActDim, 1> y = b3_;
  affine(w3t_, h2, y);
  std::array<double, kActDim> out;
  for (int i = 0; i < kActDim; ++i) out[static_cast<size_t>(i)] = math::tanh(y[i]);
  return out;
}

std::vector<double> Mlp::params() const {
  std::vector<double> out;
  out.reserve(kParamCount);
  put(w1t_, out);
  put(b1_, out);
  put(w2t_, out);
  put(b2_, out);
  put(w3t_, out);
  put(b3_, out);
  return out;
}

std::vector<double> random_params(RandomStream& rng, double stddev) {
  std::vector<double> params(kParamCount);
  for (double& p : params) p = stddev * rng.normal();
  return params;
}

std::vector<double> zero_params() { return std::vector<double>(kParamCount, 0.0); }

}  // namespace poet
