#include "run_directory/files/checkpoint_anchors.h"

#include <algorithm>

namespace poet {

void CheckpointAnchors::add(CheckpointAnchor anchor) { anchors_.push_back(std::move(anchor)); }

const CheckpointAnchor* CheckpointAnchors::before(uint64_t first_bad) const {
  for (auto it = anchors_.rbegin(); it != anchors_.rend(); ++it)
    if (it->last_batch < first_bad) return &*it;
  return nullptr;
}

void CheckpointAnchors::prune(std::span<const uint64_t> needed) {
  std::vector<const CheckpointAnchor*> keep;
  if (!anchors_.empty()) keep.push_back(&anchors_.back());
  for (const uint64_t batch : needed)
    if (const CheckpointAnchor* anchor = before(batch)) keep.push_back(anchor);
  std::vector<CheckpointAnchor> kept;
  for (CheckpointAnchor& anchor : anchors_)
    if (std::find(keep.begin(), keep.end(), &anchor) != keep.end()) kept.push_back(std::move(anchor));
  anchors_ = std::move(kept);
}

void CheckpointAnchors::keep_until(const CheckpointAnchor& anchor) {
  const uint64_t last = anchor.last_batch;
  const int iteration = anchor.next_iteration;
  std::erase_if(anchors_, [&](const CheckpointAnchor& a) {
    return a.last_batch > last || (a.last_batch == last && a.next_iteration > iteration);
  });
}

}  // namespace poet
