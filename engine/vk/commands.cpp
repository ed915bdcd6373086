#include "aperture/engine/vk/commands.h"

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

void submitAndWait(const Device& device, const std::function<void(VkCommandBuffer)>& record) {
  VkDevice vk = device.handle();

  // Resettable: a profiled frame submits its buffer step by step and begins
  // it again (SerialPassTimer::split).
  const VkCommandPoolCreateInfo poolInfo{.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                         .flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT |
                                                  VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                         .queueFamilyIndex = device.queueFamily()};
  VkCommandPool pool = VK_NULL_HANDLE;
  AAL_VK_CHECK(vkCreateCommandPool(vk, &poolInfo, nullptr, &pool));
  VkFence fence = VK_NULL_HANDLE;

  // The pool and fence are released on every path, exceptions included.
  struct Cleanup {
    VkDevice vk;
    VkCommandPool& pool;
    VkFence& fence;
    ~Cleanup() {
      if (fence != VK_NULL_HANDLE) vkDestroyFence(vk, fence, nullptr);
      vkDestroyCommandPool(vk, pool, nullptr);
    }
  } cleanup{vk, pool, fence};

  const VkCommandBufferAllocateInfo allocInfo{
      .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
      .commandPool = pool,
      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
      .commandBufferCount = 1};
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  AAL_VK_CHECK(vkAllocateCommandBuffers(vk, &allocInfo, &cmd));

  const VkCommandBufferBeginInfo begin{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                       .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
  AAL_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
  record(cmd);
  AAL_VK_CHECK(vkEndCommandBuffer(cmd));

  const VkFenceCreateInfo fenceInfo{.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  AAL_VK_CHECK(vkCreateFence(vk, &fenceInfo, nullptr, &fence));
  const VkSubmitInfo submit{
      .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &cmd};
  AAL_VK_CHECK(vkQueueSubmit(device.queue(), 1, &submit, fence));
  AAL_VK_CHECK(vkWaitForFences(vk, 1, &fence, VK_TRUE, UINT64_MAX));
}

void waitForEarlierCommands(VkCommandBuffer cmd) {
  const VkMemoryBarrier2 barrier{
      .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
      .srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
      .srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT,
      .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
      .dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT};
  const VkDependencyInfo dependency{.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                    .memoryBarrierCount = 1,
                                    .pMemoryBarriers = &barrier};
  vkCmdPipelineBarrier2(cmd, &dependency);
}

}  // namespace aal
