#include "engine/pata_ec.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "simulation/envgen/env_distance.h"
#include "simulation/es/centered_ranks.h"

namespace poet {

PataEc pata_ec(std::span<const double> scores, double low, double high) {
  std::vector<double> clipped(scores.begin(), scores.end());
  for (double& s : clipped) s = std::clamp(s, low, high);
  return centered_ranks(clipped);
}

double pata_ec_novelty(const PataEc& candidate, std::span<const PataEc> archive, int k) {
  if (k < 1) throw std::invalid_argument("pata_ec_novelty: k must be >= 1");
  std::vector<double> distances;
  distances.reserve(archive.size());
  for (const PataEc& entry : archive) {
    if (entry.size() != candidate.size())
      throw std::invalid_argument("pata_ec_novelty: an archive entry ranks " + std::to_string(entry.size()) +
                                  " agents, the candidate " + std::to_string(candidate.size()));
    double sum = 0.0;
    for (size_t i = 0; i < entry.size(); ++i) sum += (entry[i] - candidate[i]) * (entry[i] - candidate[i]);
    distances.push_back(std::sqrt(sum));
  }
  return mean_of_nearest(std::move(distances), k);
}

}  // namespace poet
