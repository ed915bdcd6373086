// The passes of a frame, in the order TerrainRenderer::record records them.
// Each records commands only: what it reads of the
// host's state was decided and written by TerrainRenderer::prepareFrame.
#pragma once

#include <vulkan/vulkan.h>

#include "aperture/engine/passes/frame_plan.h"
#include "aperture/engine/passes/pass_recording.h"

namespace aal {

// The exact mode's cap table, from its staging copy (cap_table_upload.cpp).
void recordCapTableUpload(VkCommandBuffer cmd, const Buffer& staging, const Image& table);

// The sky table for the frame's sun (sky_pass.cpp, shaders/sky_lut.glsl).
void recordSkyTable(const PassContext& pass, const FrameTargets& targets);
// The sky, drawn into the terrain pass's rendering where the terrain left the
// far plane (sky_pass.cpp).
void drawSky(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets);

// Readies the targets the terrain pass writes (terrain_pass.cpp).
void readyTerrainTargets(const PassContext& pass, const FramePlan& plan,
                         const FrameTargets& targets);
// The terrain, the base and the sky, in one rendering where the device
// allows (terrain_pass.cpp).
void recordTerrainPass(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets);
// The selected LOD patches, in the terrain pass's rendering (terrain_pass.cpp).
void drawTerrain(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets);
// The solid base under the DEM, in the terrain pass's rendering (base_pass.cpp).
void drawBase(const PassContext& pass, const FramePlan& plan);

// Obscurance/W from the terrain pass's targets (obscurance_pass.cpp,
// docs/design.md §6, §8).
void recordObscurance(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets);
// The 4x4 filter of the interleaved obscurance (obscurance_pass.cpp).
void recordObscuranceFilter(const PassContext& pass, const FramePlan& plan,
                            const FrameTargets& targets);
// Upsampling O/W and applying it onto the terrain's radiance
// (composite_pass.cpp).
void recordComposite(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets);

// Temporal accumulation at full size (FramePlan::resolve with `linear`):
// the HDR target's radiance blended with the last accumulated frame,
// reprojected, into the history and back into the HDR target
// (display_passes.cpp, shaders/resolve.glsl).
void recordAccumulation(const PassContext& pass, const FramePlan& plan,
                        const FrameTargets& targets);
// The HDR target tone-mapped into the display values (display_passes.cpp).
void recordToneMap(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets);
// The display image handed over as the frame's result, scaled up into the
// output image when drawn smaller (display_passes.cpp).
void recordDisplayHandoff(const PassContext& pass, const FramePlan& plan,
                          const FrameTargets& targets);

}  // namespace aal
