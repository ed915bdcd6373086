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

// A barrier after which the commands recorded into `cmd` start only once
// every command submitted to the queue before them (earlier frames in
// flight included) has completed, its writes visible: a frame's first
// command, so that with frames in flight only the host's work overlaps the
// device's, and a pass may rewrite an image that the frame before read at
// any stage.
void waitForEarlierCommands(VkCommandBuffer cmd);

}  // namespace aal
