#pragma once
// Centered ranks (spec §2 step 3): the i-th return becomes rank/(n − 1) − 0.5, ranks 0..n−1 in ascending order
// of return, ties broken by index (a stable sort), so equal returns still get distinct, deterministic ranks.

#include <span>
#include <vector>

namespace poet {

// One value per return, in [−0.5, 0.5]; a single return gets 0. NaN returns are not allowed (callers validate
// results at the boundary).
std::vector<double> centered_ranks(std::span<const double> returns);

}  // namespace poet
