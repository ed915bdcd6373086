#include "aperture/engine/vk/frame_sync.h"

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

namespace {
VkSemaphore makeSemaphore(VkDevice device) {
  const VkSemaphoreCreateInfo info{.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VkSemaphore semaphore = VK_NULL_HANDLE;
  AAL_VK_CHECK(vkCreateSemaphore(device, &info, nullptr, &semaphore));
  return semaphore;
}
}  // namespace

FrameSync::FrameSync(const Device& device, uint32_t imageCount) : device_(device) {
  const VkDevice vk = device.handle();
  for (Slot& slot : slots_) {
    const VkCommandPoolCreateInfo poolInfo{.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                           .flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT,
                                           .queueFamilyIndex = device.queueFamily()};
    AAL_VK_CHECK(vkCreateCommandPool(vk, &poolInfo, nullptr, &slot.pool));
    const VkCommandBufferAllocateInfo allocInfo{
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = slot.pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1};
    AAL_VK_CHECK(vkAllocateCommandBuffers(vk, &allocInfo, &slot.commands));
    // Signalled: no earlier frame to wait for.
    const VkFenceCreateInfo fenceInfo{.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO,
                                      .flags = VK_FENCE_CREATE_SIGNALED_BIT};
    AAL_VK_CHECK(vkCreateFence(vk, &fenceInfo, nullptr, &slot.done));
    slot.acquired = makeSemaphore(vk);
  }
  resize(imageCount);
}

FrameSync::~FrameSync() {
  const VkDevice vk = device_.handle();
  vkDeviceWaitIdle(vk);
  for (VkSemaphore s : rendered_) vkDestroySemaphore(vk, s, nullptr);
  for (Slot& slot : slots_) {
    vkDestroySemaphore(vk, slot.acquired, nullptr);
    vkDestroyFence(vk, slot.done, nullptr);
    vkDestroyCommandPool(vk, slot.pool, nullptr);
  }
}

void FrameSync::resize(uint32_t imageCount) {
  for (VkSemaphore s : rendered_) vkDestroySemaphore(device_.handle(), s, nullptr);
  rendered_.clear();
  for (uint32_t i = 0; i < imageCount; ++i) rendered_.push_back(makeSemaphore(device_.handle()));
}

void FrameSync::waitFor(Slot& slot) {
  AAL_VK_CHECK(vkWaitForFences(device_.handle(), 1, &slot.done, VK_TRUE, UINT64_MAX));
  if (slot.frame) device_.deletionQueue().releaseCompleted(*slot.frame);
}

void FrameSync::waitForFrameSlot() {
  waitFor(slots_[slot_]);
}

void FrameSync::waitForSubmittedFrames() {
  // Oldest first (the next slot is the least recently used).
  for (uint32_t i = 0; i < kFramesInFlight; ++i) waitFor(slots_[(slot_ + i) % kFramesInFlight]);
}

VkCommandBuffer FrameSync::beginCommands() {
  Slot& slot = slots_[slot_];
  AAL_VK_CHECK(vkResetCommandPool(device_.handle(), slot.pool, 0));
  const VkCommandBufferBeginInfo begin{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                       .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
  AAL_VK_CHECK(vkBeginCommandBuffer(slot.commands, &begin));
  return slot.commands;
}

void FrameSync::submit(uint32_t imageIndex) {
  Slot& slot = slots_[slot_];
  AAL_VK_CHECK(vkEndCommandBuffer(slot.commands));
  // Reset only now: a frame abandoned before submitting (swapchain out of
  // date) must leave the fence signalled.
  AAL_VK_CHECK(vkResetFences(device_.handle(), 1, &slot.done));
  // The swapchain image is first written by the last pass of the frame (a
  // colour attachment) or, at a reduced resolution, by the upscaling blit.
  const VkPipelineStageFlags waitStage =
      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  const VkSubmitInfo submit{.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                            .waitSemaphoreCount = 1,
                            .pWaitSemaphores = &slot.acquired,
                            .pWaitDstStageMask = &waitStage,
                            .commandBufferCount = 1,
                            .pCommandBuffers = &slot.commands,
                            .signalSemaphoreCount = 1,
                            .pSignalSemaphores = &rendered_[imageIndex]};
  AAL_VK_CHECK(vkQueueSubmit(device_.queue(), 1, &submit, slot.done));
  // What was retired while this frame was recorded waits for its fence.
  slot.frame = device_.deletionQueue().endFrame();
  slot_ = (slot_ + 1) % kFramesInFlight;
}

}  // namespace aal
