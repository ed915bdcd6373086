#include "aperture/engine/passes/frame_passes.h"

namespace aal {

namespace {

// Readies the history this frame writes; images made this frame are first
// put where a read expects them (sampled, never used: the history is not
// valid yet).
void readyHistory(VkCommandBuffer cmd, const FramePlan& plan, const FrameTargets& targets) {
  if (plan.historyFresh) {
    for (int i = 0; i < 2; ++i) {
      transitionImage(cmd, *targets.historyMeans[i], VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      transitionImage(cmd, *targets.historyPoints[i], VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
  }
  transitionImage(cmd, *targets.historyMeans[plan.historyWrite], VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  transitionImage(cmd, *targets.historyPoints[plan.historyWrite], VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
}

}  // namespace

void recordObscurance(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets) {
  const VkCommandBuffer cmd = pass.cmd;
  transitionImage(cmd, targets.ambient, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, targets.surface, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, targets.transfer, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  if (plan.temporal) readyHistory(cmd, plan, targets);
  const VkSampler nearest = pass.pipelines.nearest.handle();
  VkRenderingAttachmentInfo outputs[3] = {colorAttachment(targets.transfer, false), {}, {}};
  DescriptorWrites writes = terrainWrites(pass)
                                .buffer(kAfterTerrainTextures, pass.samples)
                                .image(kAfterTerrainTextures + 1, targets.surface.view(), nearest)
                                .image(kAfterTerrainTextures + 2, targets.ambient.view(), nearest);
  if (plan.temporal) {
    outputs[1] = colorAttachment(*targets.historyMeans[plan.historyWrite], false);
    outputs[2] = colorAttachment(*targets.historyPoints[plan.historyWrite], false);
    writes.image(kAfterTerrainTextures + 3, targets.historyMeans[plan.historyRead]->view(), nearest)
        .image(kAfterTerrainTextures + 4, targets.historyPoints[plan.historyRead]->view(), nearest);
  }
  // At half resolution the pass fills the top-left quarter of the transfer target.
  drawFullscreen(
      pass, "obscurance", plan.obscuranceExtent, outputs, plan.temporal ? 3 : 1,
      pass.pipelines.obscurance(plan.paging, plan.mode, plan.albedoSource, plan.temporal), writes);
  if (plan.temporal) {
    // What this frame wrote is what the next one reads.
    transitionImage(cmd, *targets.historyMeans[plan.historyWrite],
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    transitionImage(cmd, *targets.historyPoints[plan.historyWrite],
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  }
  transitionImage(cmd, targets.transfer, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

void recordObscuranceFilter(const PassContext& pass, const FramePlan& plan,
                            const FrameTargets& targets) {
  transitionImage(pass.cmd, targets.filtered, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  const VkRenderingAttachmentInfo filtered = colorAttachment(targets.filtered, false);
  drawFullscreen(pass, "obscurance filter", plan.obscuranceExtent, &filtered, 1,
                 pass.pipelines.filter,
                 DescriptorWrites()
                     .buffer(0, pass.uniforms)
                     .image(1, targets.transfer.view(), pass.pipelines.nearest.handle()));
  transitionImage(pass.cmd, targets.filtered, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

}  // namespace aal
