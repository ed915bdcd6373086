#include "aperture/engine/vk/serial_pass_timer.h"

#include <chrono>
#include <ctime>

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

SerialPassTimer::SerialPassTimer(const Device& device) : device_(device) {
  const VkFenceCreateInfo info{.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  AAL_VK_CHECK(vkCreateFence(device.handle(), &info, nullptr, &fence_));
}

SerialPassTimer::~SerialPassTimer() {
  vkDestroyFence(device_.handle(), fence_, nullptr);
}

void SerialPassTimer::split(VkCommandBuffer cmd, const std::string& step) {
  AAL_VK_CHECK(vkEndCommandBuffer(cmd));
  const VkSubmitInfo submit{
      .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &cmd};
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = processCpuMs();
  AAL_VK_CHECK(vkQueueSubmit(device_.queue(), 1, &submit, fence_));
  AAL_VK_CHECK(vkWaitForFences(device_.handle(), 1, &fence_, VK_TRUE, UINT64_MAX));
  const double cpuMs = processCpuMs() - cpu0;
  const double wallMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
  AAL_VK_CHECK(vkResetFences(device_.handle(), 1, &fence_));
  steps_.push_back({step, wallMs, cpuMs});
  // Begun again (an implicit reset): the frame goes on in the same buffer.
  const VkCommandBufferBeginInfo begin{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                       .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
  AAL_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
}

void SerialPassTimer::addHost(const std::string& step, double wallMs, double cpuMs) {
  steps_.push_back({step, wallMs, cpuMs});
}

}  // namespace aal
