#include "simulation/es/es_gradient.h"

#include <Eigen/Core>
#include <stdexcept>

#include "simulation/es/centered_ranks.h"
#include "simulation/es/perturbation.h"

namespace poet {

std::vector<double> es_gradient(std::span<const uint64_t> keys, std::span<const double> plus,
                                std::span<const double> minus, double sigma, bool normalize_by_sigma, size_t dim) {
  if (keys.empty()) throw std::invalid_argument("es_gradient: no perturbations");
  if (plus.size() != keys.size() || minus.size() != keys.size()) {
    throw std::invalid_argument("es_gradient: keys, plus and minus differ in size");
  }
  if (normalize_by_sigma && !(sigma > 0.0)) throw std::invalid_argument("es_gradient: sigma must be positive");

  const size_t n = keys.size();
  std::vector<double> interleaved(2 * n);
  for (size_t i = 0; i < n; ++i) {
    interleaved[2 * i] = plus[i];
    interleaved[2 * i + 1] = minus[i];
  }
  const std::vector<double> ranks = centered_ranks(interleaved);

  // ε_i is rebuilt into one buffer and added at once: memory stays at two vectors of dim, not n of them.
  std::vector<double> g(dim, 0.0);
  std::vector<double> eps(dim);
  const Eigen::Index size = static_cast<Eigen::Index>(dim);
  Eigen::Map<Eigen::VectorXd> g_map(g.data(), size);
  const Eigen::Map<const Eigen::VectorXd> eps_map(eps.data(), size);
  for (size_t i = 0; i < n; ++i) {
    fill_perturbation(keys[i], eps);
    g_map += (ranks[2 * i] - ranks[2 * i + 1]) * eps_map;
  }
  double scale = 1.0 / static_cast<double>(n);
  if (normalize_by_sigma) scale /= sigma;
  g_map *= scale;
  return g;
}

}  // namespace poet
