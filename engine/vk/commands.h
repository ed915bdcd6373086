// One-shot command recording: record, submit, wait. Used for uploads,
// readbacks and compute jobs outside the frame loop.
#pragma once

#include <functional>

#include <vulkan/vulkan.h>

namespace aal {

class Device;

// Records commands with `record` into a fresh primary command buffer, submits
// it to the device's queue and blocks until the GPU has finished.
void submitAndWait(const Device& device, const std::function<void(VkCommandBuffer)>& record);

}  // namespace aal
