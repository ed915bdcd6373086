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
  const VkCommandPoolCreateInfo poolInfo{.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                         .flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT,
                                         .queueFamilyIndex = device.queueFamily()};
  AAL_VK_CHECK(vkCreateCommandPool(vk, &poolInfo, nullptr, &pool_));
  const VkCommandBufferAllocateInfo allocInfo{
      .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
      .commandPool = pool_,
      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
      .commandBufferCount = 1};
  AAL_VK_CHECK(vkAllocateCommandBuffers(vk, &allocInfo, &commands_));
  // Signalled: no previous frame to wait for.
  const VkFenceCreateInfo fenceInfo{.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO,
                                    .flags = VK_FENCE_CREATE_SIGNALED_BIT};
  AAL_VK_CHECK(vkCreateFence(vk, &fenceInfo, nullptr, &done_));
  acquired_ = makeSemaphore(vk);
  resize(imageCount);
}

FrameSync::~FrameSync() {
  const VkDevice vk = device_.handle();
  vkDeviceWaitIdle(vk);
  for (VkSemaphore s : rendered_) vkDestroySemaphore(vk, s, nullptr);
  vkDestroySemaphore(vk, acquired_, nullptr);
  vkDestroyFence(vk, done_, nullptr);
  vkDestroyCommandPool(vk, pool_, nullptr);
}

void FrameSync::resize(uint32_t imageCount) {
  for (VkSemaphore s : rendered_) vkDestroySemaphore(device_.handle(), s, nullptr);
  rendered_.clear();
  for (uint32_t i = 0; i < imageCount; ++i) rendered_.push_back(makeSemaphore(device_.handle()));
}

void FrameSync::waitForPreviousFrame() {
  AAL_VK_CHECK(vkWaitForFences(device_.handle(), 1, &done_, VK_TRUE, UINT64_MAX));
}

VkCommandBuffer FrameSync::beginCommands() {
  AAL_VK_CHECK(vkResetCommandPool(device_.handle(), pool_, 0));
  const VkCommandBufferBeginInfo begin{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                       .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
  AAL_VK_CHECK(vkBeginCommandBuffer(commands_, &begin));
  return commands_;
}

void FrameSync::submit(uint32_t imageIndex) {
  AAL_VK_CHECK(vkEndCommandBuffer(commands_));
  // Reset only now: a frame abandoned before submitting (swapchain out of
  // date) must leave the fence signalled.
  AAL_VK_CHECK(vkResetFences(device_.handle(), 1, &done_));
  // The swapchain image is first written by the last pass of the frame (a
  // colour attachment) or, at a reduced resolution, by the upscaling blit.
  const VkPipelineStageFlags waitStage =
      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  const VkSubmitInfo submit{.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                            .waitSemaphoreCount = 1,
                            .pWaitSemaphores = &acquired_,
                            .pWaitDstStageMask = &waitStage,
                            .commandBufferCount = 1,
                            .pCommandBuffers = &commands_,
                            .signalSemaphoreCount = 1,
                            .pSignalSemaphores = &rendered_[imageIndex]};
  AAL_VK_CHECK(vkQueueSubmit(device_.queue(), 1, &submit, done_));
}

}  // namespace aal
