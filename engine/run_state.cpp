#include "engine/run_state.h"

namespace poet {

std::vector<size_t> RunState::active_indices() const {
  std::vector<size_t> out;
  for (size_t i = 0; i < pairs.size(); ++i)
    if (pairs[i].active()) out.push_back(i);
  return out;
}

const Pair* RunState::find(int id) const {
  for (const Pair& p : pairs)
    if (p.id == id) return &p;
  return nullptr;
}

}  // namespace poet
