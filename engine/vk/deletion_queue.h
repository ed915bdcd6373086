// Vulkan objects kept until the last frame that may use them has completed
// (deferred destruction, as Granite does it): code that replaces an image,
// a buffer, a pipeline or a whole scene while frames are in flight retires
// the old owner here instead of destroying it. The device owns one queue
// (Device::deletionQueue); the frame loop tells it when frames end and when
// they have completed (FrameSync), a headless frame after its wait
// (TerrainRenderer::render).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace aal {

class DeletionQueue {
 public:
  DeletionQueue() = default;
  // Destroys what is left: the owner waits for the device to be idle first.
  ~DeletionQueue() { releaseAll(); }
  DeletionQueue(const DeletionQueue&) = delete;
  DeletionQueue& operator=(const DeletionQueue&) = delete;

  // Keeps `object` (a move-only owner: an Image, a Buffer, a std::unique_ptr,
  // a vector of them) until the frame being recorded now, currentFrame(), has
  // completed on the device, then destroys it. That frame's commands, and
  // every earlier frame's, may still use the object.
  template <class T>
  void retire(T object) {
    entries_.push_back({frame_, std::make_unique<Holder<T>>(std::move(object))});
  }

  // The frame that retire() files objects under: 0 first, then one more
  // after each endFrame().
  uint64_t currentFrame() const { return frame_; }
  // The current frame's commands have been submitted (or the frame is over
  // without any): objects retired from now on belong to the next frame.
  // Returns the number of the frame that ended, for releaseCompleted.
  uint64_t endFrame() { return frame_++; }
  // Frame `frame` has completed on the device (its fence has signalled,
  // which also covers every earlier submission to the queue): destroys what
  // it and the frames before it retired, in the order they were retired.
  void releaseCompleted(uint64_t frame);
  // The device is idle and no frame is being recorded: destroys everything.
  void releaseAll();
  // Objects waiting to be destroyed.
  size_t pending() const { return entries_.size(); }

 private:
  struct Retired {
    virtual ~Retired() = default;
  };
  template <class T>
  struct Holder final : Retired {
    explicit Holder(T o) : object(std::move(o)) {}
    T object;
  };
  struct Entry {
    uint64_t frame;
    std::unique_ptr<Retired> object;
  };
  // Destroys the first `count` entries (retired in frame order).
  void releaseFirst(size_t count);

  std::vector<Entry> entries_;  // frames ascending
  uint64_t frame_ = 0;
};

}  // namespace aal
