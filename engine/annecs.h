#pragma once
// ANNECS, Enhanced POET's accumulated number of novel environments created and solved, in both of the definitions
// its peers use (spec §3, "Metrics"), computed from a run's state. The one definition of both: the engine's
// iteration report, the status socket and poet-report all count through here.

#include <vector>

#include "engine/run_state.h"

namespace poet {

inline constexpr char kAnnecsAtAdmission[] =
    "environments admitted by reproduction (they passed the minimal criterion when created) and solved since, "
    "by any agent; counted when solved";
inline constexpr char kAnnecsAtArchiving[] =
    "environments retired from the active population (archived) that had been solved by then; counted at "
    "retirement";

struct Annecs {
  int at_admission = 0;  // kAnnecsAtAdmission
  int at_archiving = 0;  // kAnnecsAtArchiving
  friend bool operator==(const Annecs&, const Annecs&) = default;
};

// Both counts at the end of `iteration` (after its transfers). A state's pairs keep their first-solved and retired
// iterations, so any earlier iteration's values can be read from a later state; an iteration the state has not
// reached yet reads as its last one. O(pairs).
Annecs annecs_at(const RunState& state, int iteration);

// annecs_at for every iteration the state has done, 0 .. next_iteration − 1, in order. O(pairs + iterations).
std::vector<Annecs> annecs_over_time(const RunState& state);

}  // namespace poet
