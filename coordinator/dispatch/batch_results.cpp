#include "coordinator/dispatch/batch_results.h"

namespace poet {

void BatchResults::start(size_t tasks) {
  results_.assign(tasks, RolloutResult{});
  have_.assign(tasks, false);
  from_.assign(tasks, WorkerId());
  final_.assign(tasks, false);
  remaining_ = tasks;
  ready_.clear();
}

void BatchResults::clear() {
  results_.clear();
  have_.clear();
  from_.clear();
  final_.clear();
  remaining_ = 0;
  ready_.clear();
}

void BatchResults::put(size_t first, std::span<const RolloutResult> results, const WorkerId& from, bool final_now) {
  for (size_t k = 0; k < results.size(); ++k) {
    const size_t t = first + k;
    results_[t] = results[k];
    if (!have_[t]) remaining_ -= 1;
    have_[t] = true;
    from_[t] = from;
  }
  if (!final_now) return;
  ready_.emplace_back(first, first + results.size());
  for (size_t t = first; t < first + results.size(); ++t) final_[t] = true;
}

std::vector<BatchResults::Range> BatchResults::withdraw(const WorkerId& from) {
  std::vector<Range> ranges;
  const auto redo = [&](size_t t) { return from_[t] == from && have_[t] && !final_[t]; };
  for (size_t t = 0; t < from_.size(); ++t) {
    if (!redo(t)) continue;
    size_t end = t;
    while (end < from_.size() && redo(end)) unset(end++);
    ranges.emplace_back(t, end);
    t = end - 1;
  }
  return ranges;
}

std::vector<BatchResults::Range> BatchResults::missing(size_t first, size_t end, size_t most) const {
  std::vector<Range> out;
  for (size_t t = first; t < end;) {
    if (have_[t]) {
      ++t;
      continue;
    }
    size_t stop = t + 1;
    while (stop < end && stop - t < most && !have_[stop]) ++stop;
    out.emplace_back(t, stop);
    t = stop;
  }
  return out;
}

std::optional<BatchResults::Answer> BatchResults::one_answer(size_t first, size_t end) const {
  if (first >= end || !have_[first]) return std::nullopt;
  const Answer answer{from_[first], final_[first]};
  for (size_t t = first; t < end; ++t)
    if (!have_[t] || from_[t] != answer.from || final_[t] != answer.final) return std::nullopt;
  return answer;
}

void BatchResults::reopen(size_t first, size_t end) {
  for (size_t t = first; t < end; ++t)
    if (have_[t] && !final_[t]) unset(t);
}

void BatchResults::unset(size_t task) {
  have_[task] = false;
  from_[task].clear();
  remaining_ += 1;
}

std::vector<BatchResults::Ready> BatchResults::take_ready(bool whole) {
  if (whole) {  // what was held back for a check is final now
    for (size_t t = 0; t < final_.size(); ++t) {
      if (final_[t]) continue;
      size_t end = t;
      while (end < final_.size() && !final_[end]) final_[end++] = true;
      ready_.emplace_back(t, end);
      t = end - 1;
    }
  }
  std::vector<Ready> out;
  for (const auto& [first, end] : std::exchange(ready_, {}))
    out.push_back(
        {first,
         {results_.begin() + static_cast<std::ptrdiff_t>(first), results_.begin() + static_cast<std::ptrdiff_t>(end)}});
  return out;
}

std::vector<RolloutResult> BatchResults::take() {
  std::vector<RolloutResult> out = std::move(results_);
  clear();
  return out;
}

}  // namespace poet
