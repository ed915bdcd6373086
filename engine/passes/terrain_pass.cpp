#include "aperture/engine/passes/frame_passes.h"

#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/gpu_timer.h"

namespace aal {

namespace {

// The selected patches: whole nodes, then each quadrant's.
void drawPatches(VkCommandBuffer cmd, const LodSelection& selection) {
  if (selection.wholeCount > 0)
    vkCmdDrawIndexed(cmd, kLodPatchIndices, selection.wholeCount, 0, 0, 0);
  uint32_t first = selection.wholeCount;
  for (uint32_t q = 0; q < 4; ++q) {
    const uint32_t count = selection.quadrantCount[q];
    if (count > 0) {
      vkCmdDrawIndexed(cmd, kLodQuadrantIndices, count, q * kLodQuadrantIndices, 0, first);
    }
    first += count;
  }
}

}  // namespace

void readyTerrainTargets(const PassContext& pass, const FramePlan& plan,
                         const FrameTargets& targets) {
  const VkCommandBuffer cmd = pass.cmd;
  if (plan.intoOutput) {
    transitionImage(cmd, plan.outputImage, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  } else {
    transitionImage(cmd, targets.display, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  }
  if (!plan.direct) {
    transitionImage(cmd, targets.hdr, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  }
  if (plan.obscurance) {
    transitionImage(cmd, targets.ambient, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    transitionImage(cmd, targets.surface, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  }
  transitionImage(cmd, targets.depth, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
}

// Pass 1 and 2, one rendering: the terrain, then the sky where the terrain
// left the far plane. With the obscurance pass the terrain also writes
// what it and the composite read (shaders/terrain_shading.glsl; cleared to
// "no surface": ambient 0 at distance 0, texel -1), which the sky leaves
// as they are (its other targets masked off; without independent blend
// state the sky follows in a second rendering with the colour and depth
// only).
void recordTerrainPass(const PassContext& pass, const FramePlan& plan,
                       const FrameTargets& targets) {
  const VkCommandBuffer cmd = pass.cmd;
  VkRenderingAttachmentInfo colors[3] = {
      plan.direct ? displayAttachment(plan, targets) : colorAttachment(targets.hdr, false),
      colorAttachment(targets.ambient, true), colorAttachment(targets.surface, true)};
  colors[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  colors[2].clearValue.color = {{-1.0f, -1.0f, 0.0f, 0.0f}};
  VkRenderingAttachmentInfo depth{.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
                                  .imageView = targets.depth.view(),
                                  .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                                  .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
                                  // Kept for the sky's rendering of its own and the temporal
                                  // reconstruction's reprojection.
                                  .storeOp = plan.skyApart || plan.resolve
                                                 ? VK_ATTACHMENT_STORE_OP_STORE
                                                 : VK_ATTACHMENT_STORE_OP_DONT_CARE,
                                  .clearValue = {.depthStencil = {.depth = 1.0f, .stencil = 0}}};
  beginRendering(cmd, plan.extent, colors, plan.obscurance ? 3 : 1, &depth);
  pass.timer.begin(cmd, "terrain");
  drawTerrain(pass, plan, targets);
  if (plan.base) drawBase(pass, plan);
  pass.timer.end(cmd);
  if (plan.skyApart) {
    vkCmdEndRendering(cmd);
    // Order the terrain's colour and depth writes before the sky's.
    transitionImage(cmd, targets.hdr, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    transitionImage(cmd, targets.depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    colors[0].loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.storeOp = plan.resolve ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE;
    beginRendering(cmd, plan.extent, colors, 1, &depth);
  }
  drawSky(pass, plan, targets);
  vkCmdEndRendering(cmd);
}

void drawTerrain(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets) {
  pass.pipelines
      .terrain(plan.paging, plan.mode, plan.albedoSource, plan.obscurance, plan.direct,
               plan.footprintProbes)
      .bind(pass.cmd,
            terrainWrites(pass)
                .buffer(kAfterTerrainTextures, pass.patches)
                .image(kAfterTerrainTextures + 1, targets.capTable.view(),
                       pass.pipelines.linear.handle()),
            nullptr);
  // Back faces the camera cannot see cost rasterization, and shading where
  // they come before the front faces that hide them (docs/rendering.md,
  // "Drawing order"); from under the sheet's open edge they show.
  vkCmdSetCullMode(pass.cmd,
                   plan.selection->backFacesHidden ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE);
  vkCmdBindIndexBuffer(pass.cmd, pass.scene.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
  drawPatches(pass.cmd, *plan.selection);
}

}  // namespace aal
