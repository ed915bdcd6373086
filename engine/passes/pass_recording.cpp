#include "aperture/engine/passes/pass_recording.h"

#include <algorithm>
#include <vector>

#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/gpu_timer.h"

namespace aal {

namespace {

// The image bound as page `page` of a kind: the scene's, its first where
// it has fewer (the shaders never pick them). The horizons' second moments
// (TerrainScene::horizonMomentPages) take the slope kind's pages 2 and 3:
// the slopes are in the heights' pages, two at most (planTerrainTiles), so
// those are never the slopes' (shaders/terrain_textures.glsl,
// terrainHorizonMomentsLod). No binding of their own, so no pipeline's
// layout changes.
const Image& terrainPageImage(const std::vector<Image>& pages, const TerrainScene& scene,
                              uint32_t page) {
  static_assert(kTerrainTilePages == 4);
  const std::vector<Image>& moments = scene.horizonMomentPages();
  if (&pages == &scene.slopePages() && page >= 2 && !moments.empty()) {
    return moments[std::min<size_t>(page - 2, moments.size() - 1)];
  }
  return page < pages.size() ? pages[page] : pages.front();
}

}  // namespace

static_assert(AAL_TERRAIN_TILE_PAGES == kTerrainTilePages);

VkRenderingAttachmentInfo colorAttachment(const Image& image, bool clear) {
  return {.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
          .imageView = image.view(),
          .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
          .loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_DONT_CARE,
          .storeOp = VK_ATTACHMENT_STORE_OP_STORE};
}

VkRenderingAttachmentInfo displayAttachment(const FramePlan& plan, const FrameTargets& targets) {
  VkRenderingAttachmentInfo display = colorAttachment(targets.display, false);
  if (plan.intoOutput) display.imageView = plan.outputView;
  return display;
}

void beginRendering(VkCommandBuffer cmd, VkExtent2D extent, const VkRenderingAttachmentInfo* colors,
                    uint32_t colorCount, const VkRenderingAttachmentInfo* depth) {
  const VkRect2D area{.offset = {0, 0}, .extent = extent};
  const VkRenderingInfo info{.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                             .renderArea = area,
                             .layerCount = 1,
                             .colorAttachmentCount = colorCount,
                             .pColorAttachments = colors,
                             .pDepthAttachment = depth};
  vkCmdBeginRendering(cmd, &info);
  const VkViewport viewport{.x = 0,
                            .y = 0,
                            .width = float(extent.width),
                            .height = float(extent.height),
                            .minDepth = 0,
                            .maxDepth = 1};
  const VkRect2D& scissor = area;
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

void drawFullscreen(const PassContext& pass, const char* name, VkExtent2D extent,
                    const VkRenderingAttachmentInfo* targets, uint32_t targetCount,
                    const GraphicsPipeline& pipeline, const DescriptorWrites& writes) {
  pass.timer.begin(pass.cmd, name);
  beginRendering(pass.cmd, extent, targets, targetCount, nullptr);
  pipeline.bind(pass.cmd, writes, nullptr);
  vkCmdDraw(pass.cmd, 3, 1, 0, 0);
  vkCmdEndRendering(pass.cmd);
  pass.timer.end(pass.cmd);
}

DescriptorWrites terrainWrites(const PassContext& pass) {
  const TerrainScene& scene = pass.scene;
  DescriptorWrites writes;
  writes.buffer(0, pass.uniforms);
  uint32_t binding = AAL_TERRAIN_TEXTURE_BINDING;
  static_assert(AAL_TERRAIN_TEXTURE_KINDS == 4);
  for (const std::vector<Image>* pages :
       {&scene.heightPages(), &scene.aperturePages(), &scene.albedoPages(), &scene.slopePages()}) {
    for (uint32_t page = 0; page < kTerrainTilePages; ++page) {
      writes.image(binding++, terrainPageImage(*pages, scene, page).view(),
                   pass.pipelines.terrainSampler.handle());
    }
  }
  return writes;
}

}  // namespace aal
