// DeletionQueue: an object retired while frame N is recorded is destroyed
// once frame N has completed, not before.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "aperture/engine/vk/deletion_queue.h"

namespace aal {
namespace {

// Appends its id to a log when destroyed (a moved-from one does not).
class Probe {
 public:
  Probe(std::vector<int>& log, int id) : log_(&log), id_(id) {}
  Probe(Probe&& other) noexcept : log_(std::exchange(other.log_, nullptr)), id_(other.id_) {}
  Probe& operator=(Probe&&) = delete;
  ~Probe() {
    if (log_) log_->push_back(id_);
  }

 private:
  std::vector<int>* log_;
  int id_;
};

TEST(FrameDeletionQueue, ObjectLivesUntilItsFrameHasCompleted) {
  std::vector<int> destroyed;
  DeletionQueue queue;
  EXPECT_EQ(queue.currentFrame(), 0u);
  queue.retire(Probe(destroyed, 1));
  const uint64_t first = queue.endFrame();
  queue.retire(Probe(destroyed, 2));
  const uint64_t second = queue.endFrame();
  EXPECT_EQ(first, 0u);
  EXPECT_EQ(second, 1u);
  EXPECT_TRUE(destroyed.empty()) << "submitted is not completed";
  EXPECT_EQ(queue.pending(), 2u);

  queue.releaseCompleted(first);
  EXPECT_EQ(destroyed, std::vector<int>{1});
  queue.releaseCompleted(second);
  EXPECT_EQ(destroyed, (std::vector<int>{1, 2}));
  EXPECT_EQ(queue.pending(), 0u);
}

TEST(FrameDeletionQueue, ObjectRetiredAfterAFrameEndedWaitsForTheNextOne) {
  std::vector<int> destroyed;
  DeletionQueue queue;
  const uint64_t submitted = queue.endFrame();
  // Retired while frame 1 is recorded: frame 0's completion does not free it.
  queue.retire(Probe(destroyed, 7));
  queue.releaseCompleted(submitted);
  EXPECT_TRUE(destroyed.empty());
  queue.releaseCompleted(queue.endFrame());
  EXPECT_EQ(destroyed, std::vector<int>{7});
}

TEST(FrameDeletionQueue, CompletionCoversEarlierFramesInRetireOrder) {
  std::vector<int> destroyed;
  DeletionQueue queue;
  for (int id = 0; id < 3; ++id) {
    queue.retire(Probe(destroyed, id));
    queue.retire(Probe(destroyed, 10 + id));
    queue.endFrame();
  }
  // A fence covers every earlier submission: frame 1 done, frame 0 too.
  queue.releaseCompleted(1);
  EXPECT_EQ(destroyed, (std::vector<int>{0, 10, 1, 11}));
  EXPECT_EQ(queue.pending(), 2u);
}

TEST(FrameDeletionQueue, ReleaseAllAndTheQueuesEndDestroyEverything) {
  std::vector<int> destroyed;
  {
    DeletionQueue queue;
    queue.retire(Probe(destroyed, 1));
    queue.releaseAll();
    EXPECT_EQ(destroyed, std::vector<int>{1});
    queue.retire(Probe(destroyed, 2));
  }
  EXPECT_EQ(destroyed, (std::vector<int>{1, 2}));
}

}  // namespace
}  // namespace aal
