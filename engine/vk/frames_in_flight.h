// How many frames the windowed loop lets the CPU record ahead of the GPU:
// FrameSync keeps one command buffer, fence and acquire semaphore per frame
// in flight, and DeletionQueue keeps a retired object until the frames that
// may use it have completed (docs/viewer.md, "Frames in flight").
#pragma once

#include <cstdint>

namespace aal {

// Raising it is checked, not audited: the code that still reuses one
// resource in place every frame (the renderer's host-written uniforms and
// LOD patches, the viewer's read of the last frame's GPU timer)
// static_asserts on this value, and needs one copy per frame in flight
// first.
inline constexpr uint32_t kFramesInFlight = 1;
static_assert(kFramesInFlight >= 1, "at least the frame being drawn");

}  // namespace aal
