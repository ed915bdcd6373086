#include "aperture/engine/vk/gpu_timer.h"

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

GpuTimer::GpuTimer(const Device& device, uint32_t maxPasses)
    : device_(device.handle()), capacity_(2 * maxPasses) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical(), &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical(), &count, families.data());
  supported_ = families[device.queueFamily()].timestampValidBits > 0 &&
               device.properties().limits.timestampPeriod > 0;
  nanosecondsPerTick_ = device.properties().limits.timestampPeriod;
  const VkQueryPoolCreateInfo info{.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                   .queryType = VK_QUERY_TYPE_TIMESTAMP,
                                   .queryCount = capacity_};
  AAL_VK_CHECK(vkCreateQueryPool(device_, &info, nullptr, &pool_));
}

GpuTimer::~GpuTimer() {
  if (pool_ != VK_NULL_HANDLE) vkDestroyQueryPool(device_, pool_, nullptr);
}

void GpuTimer::reset(VkCommandBuffer cmd) {
  vkCmdResetQueryPool(cmd, pool_, 0, capacity_);
  passes_.clear();
}

void GpuTimer::begin(VkCommandBuffer cmd, const std::string& pass) {
  if (!supported_ || 2 * passes_.size() >= capacity_) return;
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, pool_,
                       static_cast<uint32_t>(2 * passes_.size()));
  passes_.push_back(pass);
}

void GpuTimer::end(VkCommandBuffer cmd) {
  if (!supported_ || passes_.empty()) return;
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, pool_,
                       static_cast<uint32_t>(2 * passes_.size() - 1));
}

std::vector<std::pair<std::string, double>> GpuTimer::results() const {
  std::vector<std::pair<std::string, double>> out;
  if (!supported_ || passes_.empty()) return out;
  std::vector<uint64_t> ticks(2 * passes_.size());
  AAL_VK_CHECK(vkGetQueryPoolResults(
      device_, pool_, 0, static_cast<uint32_t>(ticks.size()), ticks.size() * sizeof(uint64_t),
      ticks.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  for (size_t i = 0; i < passes_.size(); ++i) {
    out.emplace_back(passes_[i], (ticks[2 * i + 1] - ticks[2 * i]) * nanosecondsPerTick_ * 1e-6);
  }
  return out;
}

}  // namespace aal
