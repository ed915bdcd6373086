// How many frames the windowed loop lets the CPU record ahead of the GPU:
// FrameSync keeps one command buffer, fence and acquire semaphore per frame
// in flight, the renderer one copy of each host-written buffer and of its
// GPU timer per slot (FrameOutput::frameSlot), and DeletionQueue keeps a
// retired object until the frames that may use it have completed
// (docs/viewer.md, "Frames in flight").
#pragma once

#include <cstdint>

namespace aal {

// Two: the host prepares and records frame N + 1 while the device draws
// frame N. More would only add latency: the host's part of a frame is far
// shorter than the device's.
inline constexpr uint32_t kFramesInFlight = 2;
static_assert(kFramesInFlight >= 1, "at least the frame being drawn");

}  // namespace aal
