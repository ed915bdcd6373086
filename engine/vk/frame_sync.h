// Per-frame synchronisation for a window: one frame in flight (the renderer
// writes its uniforms while recording, so the previous frame must have
// finished), a command buffer, a fence, and the semaphores that order
// acquire -> render -> present.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

class Device;

class FrameSync {
 public:
  // `imageCount`: swapchain images (one "rendered" semaphore each).
  FrameSync(const Device& device, uint32_t imageCount);
  ~FrameSync();
  FrameSync(const FrameSync&) = delete;
  FrameSync& operator=(const FrameSync&) = delete;

  // Blocks until the previous frame's commands have finished.
  void waitForPreviousFrame();
  // Resets and begins the frame's command buffer (after waitForPreviousFrame).
  VkCommandBuffer beginCommands();
  // Ends and submits the commands: they wait for acquired() before the
  // colour attachment output and transfer stages (the first write to the
  // swapchain image is the frame's last pass, or the blit scaling it up) and
  // signal rendered(imageIndex) and the frame fence.
  void submit(uint32_t imageIndex);

  VkSemaphore acquired() const { return acquired_; }
  VkSemaphore rendered(uint32_t imageIndex) const { return rendered_[imageIndex]; }
  // After the swapchain was recreated with another image count (device idle).
  void resize(uint32_t imageCount);

 private:
  const Device& device_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer commands_ = VK_NULL_HANDLE;
  VkFence done_ = VK_NULL_HANDLE;
  VkSemaphore acquired_ = VK_NULL_HANDLE;
  std::vector<VkSemaphore> rendered_;
};

}  // namespace aal
