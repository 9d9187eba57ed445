#pragma once
// Perturbation vectors rebuilt from small keys (spec §2): ε(key) is a pure function of the key, so a job carries
// a 64-bit key instead of 2804 numbers and the coordinator rebuilds the same ε to form the gradient. No noise
// table: each ε is drawn from the counter-based RandomStream(key).

#include <cstdint>
#include <span>
#include <vector>

namespace poet {

// Fills out with independent N(0, 1) values of the stream `key`. Element i depends only on (key, i) and on
// out.size() only through which elements exist (a longer vector extends a shorter one).
void fill_perturbation(uint64_t key, std::span<double> out);

// The first n values of ε(key), as fill_perturbation gives them.
std::vector<double> perturbation(uint64_t key, size_t n);

// out[j] = theta[j] + sign·sigma·ε(key)[j]; sign is +1 or −1. out and theta have the same size and may alias.
void perturb(std::span<const double> theta, uint64_t key, int sign, double sigma, std::span<double> out);

}  // namespace poet
