// GPU time per pass from timestamp queries.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

class Device;

class GpuTimer {
 public:
  // Room for `maxPasses` passes per frame.
  GpuTimer(const Device& device, uint32_t maxPasses);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  // Resets the queries; record before the first pass of a frame.
  void reset(VkCommandBuffer cmd);
  void begin(VkCommandBuffer cmd, const std::string& pass);
  void end(VkCommandBuffer cmd);
  // Milliseconds per pass of the last frame, after its submission finished.
  // Empty when the queue has no timestamp support.
  std::vector<std::pair<std::string, double>> results() const;

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t capacity_ = 0;
  double nanosecondsPerTick_ = 1;
  bool supported_ = false;
  std::vector<std::string> passes_;
};

}  // namespace aal
