// A frame in two steps: TerrainRenderer::prepareFrame does the host's work
// (LOD selection, the horizon re-lay, the uniforms) and decides which passes
// run and where they write; the passes (engine/passes/frame_passes.h) then
// only record commands from that decision.
#pragma once

#include <cstdint>

#include <vulkan/vulkan.h>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include "aperture/engine/passes/pass_pipelines.h"
#include "aperture/terrain/light/shading.h"
#include "aperture/terrain/view/quadtree_lod.h"

namespace aal {

// shaders/resolve.glsl's push constants.
struct ResolveConstants {
  // This frame's clip space without the jitter to the last accumulated frame's.
  glm::mat4 reproject{1.0f};
  glm::vec2 jitter{0.0f};  // drawn pixels
  float currentWeight = 1.0f;
  int32_t historyValid = 0;
  float centreFalloff = 0.0f;  // a sample's weight: 1 / (1 + centreFalloff d²), d in output pixels
  float unused[3] = {};
};
static_assert(sizeof(ResolveConstants) == 96, "the shader's push-constant block, padded");

struct FramePlan {
  ShadingMode mode = ShadingMode::Approx;
  int albedoSource = 0;  // AAL_ALBEDO_*
  TexturePaging paging = TexturePaging::OnePage;
  int footprintProbes = 1;
  const LodSelection* selection = nullptr;  // the patches the terrain pass draws
  bool base = false;                        // the solid base under the DEM

  VkExtent2D extent{0, 0};      // drawn: the renderer's size, or less (FrameOutput)
  VkExtent2D fullExtent{0, 0};  // the renderer's size, which the upscale fills
  // FrameOutput::linear: the radiance is kept in the HDR target and tone-mapped
  // in a last pass.
  bool linear = false;
  // Without linear output or the obscurance pass the terrain and the sky
  // write display values at once: no HDR target, no tone-map pass.
  bool direct = false;
  // The pass that writes display values writes FrameOutput::image itself
  // (drawn at full size), else displayImage(), which `upscale` scales up into
  // FrameOutput::image when that is set.
  bool intoOutput = false;
  bool upscale = false;
  VkImage outputImage = VK_NULL_HANDLE;
  VkImageView outputView = VK_NULL_HANDLE;

  // The obscurance/W pass, and the composite that applies it.
  bool obscurance = false;
  // Without independent blend state the sky cannot leave the G-buffer's
  // other targets as they are: it follows in a rendering of its own.
  bool skyApart = false;
  VkExtent2D obscuranceExtent{0, 0};  // extent, or half of it at half resolution
  bool interleaved = false;           // then the 4x4 filter runs
  // Obscurance reuse: the history images read and written (indices into
  // FrameTargets' pairs), and whether they were just made.
  bool temporal = false;
  bool historyFresh = false;
  int historyRead = 0, historyWrite = 1;

  // Temporal accumulation (FrameOutput::temporal): in place of the upscale
  // (display values), or at full size into the linear radiance before the
  // tone map (`linear`). The history image read (an index into
  // FrameTargets::resolveHistory), the other written.
  bool resolve = false;
  int resolveRead = 0;
  ResolveConstants resolveConstants;

  // The exact mode's cap table was remade on the host: record its upload.
  bool capTableUpload = false;
};

}  // namespace aal
