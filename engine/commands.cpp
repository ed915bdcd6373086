#include "commands.h"

#include "device.h"
#include "vk_check.h"

namespace aal {

void submitAndWait(const Device& device, const std::function<void(VkCommandBuffer)>& record) {
  VkDevice vk = device.handle();

  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  poolInfo.queueFamilyIndex = device.queueFamily();
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

  VkCommandBufferAllocateInfo allocInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocInfo.commandPool = pool;
  allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocInfo.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  AAL_VK_CHECK(vkAllocateCommandBuffers(vk, &allocInfo, &cmd));

  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  AAL_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
  record(cmd);
  AAL_VK_CHECK(vkEndCommandBuffer(cmd));

  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  AAL_VK_CHECK(vkCreateFence(vk, &fenceInfo, nullptr, &fence));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  AAL_VK_CHECK(vkQueueSubmit(device.queue(), 1, &submit, fence));
  AAL_VK_CHECK(vkWaitForFences(vk, 1, &fence, VK_TRUE, UINT64_MAX));
}

}  // namespace aal
