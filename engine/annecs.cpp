#include "engine/annecs.h"

#include <algorithm>

namespace poet {
namespace {

// The iteration at which a pair enters each count, or kNone when it does not (yet). The first-solved iteration
// is frozen once a pair retires, so a retired pair that is solved was solved by its retirement.
int counted_at_admission(const Pair& p) {
  return p.parent_id != kNone && p.solved() ? p.first_solved_iteration : kNone;
}
int counted_at_archiving(const Pair& p) { return !p.active() && p.solved() ? p.retired_iteration : kNone; }

}  // namespace

Annecs annecs_at(const RunState& state, int iteration) {
  Annecs a;
  const auto by = [iteration](int counted) { return counted != kNone && counted <= iteration ? 1 : 0; };
  for (const Pair& p : state.pairs) {
    a.at_admission += by(counted_at_admission(p));
    a.at_archiving += by(counted_at_archiving(p));
  }
  return a;
}

std::vector<Annecs> annecs_over_time(const RunState& state) {
  // each pair's increment at its iteration, then accumulated
  std::vector<Annecs> series(static_cast<size_t>(std::max(0, state.next_iteration)));
  const auto slot = [&](int counted) -> Annecs* {
    if (counted == kNone || counted < 0 || counted >= state.next_iteration) return nullptr;
    return &series[static_cast<size_t>(counted)];
  };
  for (const Pair& p : state.pairs) {
    if (Annecs* s = slot(counted_at_admission(p))) s->at_admission += 1;
    if (Annecs* s = slot(counted_at_archiving(p))) s->at_archiving += 1;
  }
  for (size_t t = 1; t < series.size(); ++t) {
    series[t].at_admission += series[t - 1].at_admission;
    series[t].at_archiving += series[t - 1].at_archiving;
  }
  return series;
}

}  // namespace poet
