// What every pass records with (the command buffer, the scene it reads, the
// pipelines, the timer, the frame's buffers and targets), and the steps
// passes share: attachments, dynamic rendering, the terrain's bindings.
#pragma once

#include <cstdint>

#include <vulkan/vulkan.h>

#include "aperture/engine/passes/frame_plan.h"
#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/descriptors.h"
#include "aperture/engine/vk/image.h"
#include "aperture/shaders/config.h"

namespace aal {

class GpuTimer;
class TerrainScene;

struct PassContext {
  VkCommandBuffer cmd;
  const TerrainScene& scene;
  PassPipelines& pipelines;  // non-const: variants are made on first use
  GpuTimer& timer;
  const Buffer& uniforms;  // FrameUniforms
  const Buffer& patches;   // LodPatch instances of the frame
  const Buffer& samples;   // obscurance sample offsets
};

// The renderer's images, as passes read and write them.
struct FrameTargets {
  const Image& hdr;
  const Image& depth;
  const Image& display;
  // Terrain pass outputs for the obscurance pass and the composite (see
  // shaders/terrain_shading.glsl), and the per-pixel O/W.
  const Image& ambient;
  const Image& surface;
  const Image& transfer;
  const Image& filtered;
  const Image& skyTable;
  const Image& capTable;
  // Obscurance reuse; null until the first frame that reuses.
  const Image* historyMeans[2];
  const Image* historyPoints[2];
  // Temporal reconstruction; null until the first frame that rebuilds.
  const Image* resolveHistory[2];
};

// Binding of the first descriptor after the terrain textures.
constexpr uint32_t kAfterTerrainTextures = AAL_TERRAIN_TEXTURES_END;

VkRenderingAttachmentInfo colorAttachment(const Image& image, bool clear);

// Where the frame's display values go: the output image or displayImage().
VkRenderingAttachmentInfo displayAttachment(const FramePlan& plan, const FrameTargets& targets);

// Begins dynamic rendering into `colorCount` colour (and an optional depth)
// attachments covering the whole target, with the viewport and scissor set to
// match.
void beginRendering(VkCommandBuffer cmd, VkExtent2D extent, const VkRenderingAttachmentInfo* colors,
                    uint32_t colorCount, const VkRenderingAttachmentInfo* depth);

// A fullscreen triangle (shaders/fullscreen.vert) in a rendering of its own
// into `targets`, timed as `name`. The timestamps go around the whole
// rendering: lavapipe rasterizes when a rendering ends, so one inside it
// misses the work.
void drawFullscreen(const PassContext& pass, const char* name, VkExtent2D extent,
                    const VkRenderingAttachmentInfo* targets, uint32_t targetCount,
                    const GraphicsPipeline& pipeline, const DescriptorWrites& writes);

// The frame's uniforms and the scene's texture pages.
DescriptorWrites terrainWrites(const PassContext& pass);

}  // namespace aal
