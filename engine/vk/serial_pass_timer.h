// Wall-clock and CPU time per step of a frame, measured by submitting each
// step on its own and waiting for it. Timestamp queries cannot tell this on
// a CPU device: lavapipe writes a timestamp when its queue thread reaches
// the command, while llvmpipe shades a rendering's draws later, on its
// worker threads, when the rendering is flushed; so a pass's interval holds
// little of its own work and the next one's holds the rest
// (docs/performance.md, "Where a frame's time goes"). Serialising costs the
// overlap between steps: the steps' sum exceeds the frame in one submission.
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

class Device;

class SerialPassTimer {
 public:
  struct Step {
    std::string name;
    double wallMs = 0;  // from the submission to the fence
    double cpuMs = 0;   // the process's CPU time meanwhile (every thread: the driver's too)
  };

  explicit SerialPassTimer(const Device& device);
  ~SerialPassTimer();
  SerialPassTimer(const SerialPassTimer&) = delete;
  SerialPassTimer& operator=(const SerialPassTimer&) = delete;

  // Ends `cmd` (outside any rendering), submits it, waits for it and begins
  // it again: what was recorded since the last split is charged to `step`.
  // The buffer's pool must let buffers be reset one by one
  // (VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT).
  void split(VkCommandBuffer cmd, const std::string& step);
  // Host work charged to a step of its own (the host's part of the frame).
  void addHost(const std::string& step, double wallMs, double cpuMs);
  const std::vector<Step>& steps() const { return steps_; }
  void clear() { steps_.clear(); }

 private:
  const Device& device_;
  VkFence fence_ = VK_NULL_HANDLE;
  std::vector<Step> steps_;
};

// The process's CPU time in milliseconds (every thread).
double processCpuMs();

}  // namespace aal
