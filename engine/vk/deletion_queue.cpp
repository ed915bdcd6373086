#include "aperture/engine/vk/deletion_queue.h"

#include <algorithm>
#include <iterator>

namespace aal {

void DeletionQueue::releaseCompleted(uint64_t frame) {
  const auto end = std::find_if(entries_.begin(), entries_.end(),
                                [frame](const Entry& e) { return e.frame > frame; });
  releaseFirst(size_t(std::distance(entries_.begin(), end)));
}

void DeletionQueue::releaseAll() {
  releaseFirst(entries_.size());
}

void DeletionQueue::releaseFirst(size_t count) {
  // Moved out before they are destroyed: a destructor may retire more.
  std::vector<Entry> done(std::make_move_iterator(entries_.begin()),
                          std::make_move_iterator(entries_.begin() + std::ptrdiff_t(count)));
  entries_.erase(entries_.begin(), entries_.begin() + std::ptrdiff_t(count));
  for (Entry& e : done) e.object.reset();
}

}  // namespace aal
