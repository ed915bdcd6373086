// Per-frame synchronisation for a window: kFramesInFlight frames
// (engine/vk/frames_in_flight.h), each with its command buffer, fence and
// acquire semaphore, and one "rendered" semaphore per swapchain image, which
// order acquire -> render -> present. It tells the device's DeletionQueue
// when a frame is submitted and when it has completed, so that what a frame
// retired is destroyed once no frame can use it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <vulkan/vulkan.h>

#include "aperture/engine/vk/frames_in_flight.h"

namespace aal {

class Device;

class FrameSync {
 public:
  // `imageCount`: swapchain images (one "rendered" semaphore each).
  FrameSync(const Device& device, uint32_t imageCount);
  ~FrameSync();
  FrameSync(const FrameSync&) = delete;
  FrameSync& operator=(const FrameSync&) = delete;

  // Blocks until the frame that last used this frame's slot (kFramesInFlight
  // frames back) has completed, then destroys what it and the frames before
  // it retired. Call first in a frame: the slot's command buffer, fence and
  // acquire semaphore are free after it.
  void waitForFrameSlot();
  // Blocks until every submitted frame has completed (a read-back of the
  // last frame), destroying what they retired.
  void waitForSubmittedFrames();
  // Resets and begins the frame's command buffer (after waitForFrameSlot).
  VkCommandBuffer beginCommands();
  // Ends and submits the commands: they wait for acquired() before the
  // colour attachment output and transfer stages (the first write to the
  // swapchain image is the frame's last pass, or the blit scaling it up) and
  // signal rendered(imageIndex) and the frame's fence. The next frame takes
  // the next slot.
  void submit(uint32_t imageIndex);

  // The frame's slot, 0 .. kFramesInFlight - 1: the frame kFramesInFlight
  // back used it, and has completed after waitForFrameSlot (what the
  // renderer's per-slot copies are indexed by, FrameOutput::frameSlot).
  uint32_t slot() const { return slot_; }
  // The frame's acquire semaphore.
  VkSemaphore acquired() const { return slots_[slot_].acquired; }
  VkSemaphore rendered(uint32_t imageIndex) const { return rendered_[imageIndex]; }
  // After the swapchain was recreated with another image count (device idle).
  void resize(uint32_t imageCount);

 private:
  struct Slot {
    VkCommandPool pool = VK_NULL_HANDLE;
    VkCommandBuffer commands = VK_NULL_HANDLE;
    VkFence done = VK_NULL_HANDLE;
    VkSemaphore acquired = VK_NULL_HANDLE;
    // DeletionQueue's number of the frame last submitted from it.
    std::optional<uint64_t> frame;
  };
  // Waits for the slot's fence and releases what its frame retired.
  void waitFor(Slot& slot);

  const Device& device_;
  std::array<Slot, kFramesInFlight> slots_;
  uint32_t slot_ = 0;  // the frame being recorded
  std::vector<VkSemaphore> rendered_;
};

}  // namespace aal
