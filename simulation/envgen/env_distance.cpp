#include "simulation/envgen/env_distance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "simulation/enum_names.h"

namespace poet {

EnvVector env_vector(const EnvEncoding& e) {
  EnvVector v{e.roughness, 0.0, 0.0, 0.0, 0.0};
  if (e.pit_gap) {
    v[1] = e.pit_gap->lo;
    v[2] = e.pit_gap->hi;
  }
  if (e.stump_height) {
    v[3] = e.stump_height->lo;
    v[4] = e.stump_height->hi;
  }
  return v;
}

namespace {

double distance(const EnvVector& va, const EnvVector& vb, bool normalized) {
  double sum = 0.0;
  for (size_t i = 0; i < va.size(); ++i) {
    const double d = normalized ? va[i] / kEnvVectorMax[i] - vb[i] / kEnvVectorMax[i] : va[i] - vb[i];
    sum += d * d;
  }
  const double norm = std::sqrt(sum);
  return normalized ? norm / std::sqrt(static_cast<double>(va.size())) : norm;
}

}  // namespace

double euclidean_distance(const EnvEncoding& a, const EnvEncoding& b) {
  return distance(env_vector(a), env_vector(b), false);
}

double normalized_distance(const EnvEncoding& a, const EnvEncoding& b) {
  return distance(env_vector(a), env_vector(b), true);
}

double normalized_distance(const EnvVector& a, const EnvVector& b) { return distance(a, b, true); }

double mean_of_nearest(std::vector<double> distances, int k) {
  if (k < 1) throw std::invalid_argument("novelty: k must be >= 1");
  if (distances.empty()) return 0.0;
  std::sort(distances.begin(), distances.end());
  const size_t n = std::min(distances.size(), static_cast<size_t>(k));
  double sum = 0.0;
  for (size_t i = 0; i < n; ++i) sum += distances[i];
  return sum / static_cast<double>(n);
}

double novelty(const EnvEncoding& candidate, std::span<const EnvEncoding> archive, int k, bool normalized) {
  std::vector<double> distances;
  distances.reserve(archive.size());
  const EnvVector c = env_vector(candidate);
  for (const EnvEncoding& e : archive) distances.push_back(distance(c, env_vector(e), normalized));
  return mean_of_nearest(std::move(distances), k);
}

Difficulty difficulty(const EnvVector& e) {
  int met = 0;
  if (e[4] >= kChallengingStumpHeight) ++met;
  if (e[2] >= kChallengingGap) ++met;
  if (e[0] >= kChallengingRoughness) ++met;
  return static_cast<Difficulty>(met);
}

Difficulty difficulty(const EnvEncoding& e) { return difficulty(env_vector(e)); }

ObstacleMeasures obstacle_measures(const EnvVector& e) { return {e[0], e[2], e[4]}; }

void raise_frontier(ObstacleMeasures& frontier, const EnvVector& e) {
  const ObstacleMeasures m = obstacle_measures(e);
  for (size_t i = 0; i < m.size(); ++i) frontier[i] = std::max(frontier[i], m[i]);
}

std::string_view to_string(Difficulty d) {
  static constexpr std::array<std::string_view, 4> kNames = {"easy", "challenging", "very challenging",
                                                             "extremely challenging"};
  return enum_name(d, kNames, "unknown");
}

std::string_view level_label(const EnvEncoding& encoding) {
  return encoding.is_cppn() ? "CPPN terrain" : to_string(difficulty(encoding));
}

}  // namespace poet
