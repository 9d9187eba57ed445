#pragma once
// PATA-EC, Enhanced POET's environment characterisation (Wang et al. 2020): an environment described by how a
// fixed list of agents rank on it, and a candidate's novelty as the mean distance to the nearest such
// descriptions. Pure arithmetic on scores; the engine gathers the scores (reproduction.cpp).

#include <span>
#include <vector>

namespace poet {

// One value per agent, in the agents' order, each in [−0.5, 0.5].
using PataEc = std::vector<double>;

// The scores of the agents on one environment, each clipped to [low, high], as centred ranks (es/centered_ranks:
// rank/(n − 1) − 0.5 in ascending order of score). Clipping makes ties common: tied scores get distinct ranks in
// agent order (a stable sort, where the authors' numpy argsort leaves the order unspecified), so two environments
// every agent fails alike get the same PATA-EC. One agent gets 0 (the authors' 0/0 is NaN). Requires low ≤ high
// and no NaN score.
PataEc pata_ec(std::span<const double> scores, double low, double high);

// The mean Euclidean distance from candidate to its k nearest archive entries; the mean over all of them when the
// archive has fewer than k, and 0 for an empty archive (as envgen/env_distance's novelty). Throws
// std::invalid_argument when k < 1 or an entry's length differs from the candidate's.
double pata_ec_novelty(const PataEc& candidate, std::span<const PataEc> archive, int k);

}  // namespace poet
