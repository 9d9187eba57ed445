#pragma once
// The ES gradient estimate of spec §2 step 4 from mirrored returns.

#include <cstdint>
#include <span>
#include <vector>

namespace poet {

// The returns of one ES step: perturbation i was evaluated at θ + σε(keys[i]) (plus[i]) and θ − σε(keys[i])
// (minus[i]). Ranks are taken over all 2n returns interleaved as plus0, minus0, plus1, minus1, … (the
// reference's layout, which decides the order of ties). Then g = Σᵢ (rank⁺ᵢ − rank⁻ᵢ) ε(keys[i]) / n, divided
// by sigma when normalize_by_sigma. Returns a vector of `dim` numbers. Throws std::invalid_argument when the
// spans differ in size or are empty.
std::vector<double> es_gradient(std::span<const uint64_t> keys, std::span<const double> plus,
                                std::span<const double> minus, double sigma, bool normalize_by_sigma, size_t dim);

}  // namespace poet
