// One-shot command recording: record, submit, wait. Used for uploads,
// readbacks and compute jobs outside the frame loop.
#pragma once

#include <functional>

#include <vulkan/vulkan.h>

namespace aal {

class Device;

// Records commands with `record` into a fresh primary command buffer, submits
// it to the device's queue and blocks until the GPU has finished. It destroys
// nothing from the device's DeletionQueue, although every earlier submission
// has then completed too: it may run while a windowed frame is recorded (the
// horizon re-lay), whose commands still use what that frame retired. A
// headless frame ends itself after its wait (TerrainRenderer::render).
void submitAndWait(const Device& device, const std::function<void(VkCommandBuffer)>& record);

}  // namespace aal
