#include "aperture/engine/passes/frame_passes.h"

#include "aperture/engine/vk/gpu_timer.h"

namespace aal {

void recordComposite(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets) {
  const VkCommandBuffer cmd = pass.cmd;
  const VkSampler nearest = pass.pipelines.nearest.handle();
  const Image& result = plan.interleaved ? targets.filtered : targets.transfer;
  DescriptorWrites composite;
  composite.buffer(0, pass.uniforms)
      .image(1, result.view(), nearest)
      .image(2, targets.ambient.view(), nearest);
  pass.timer.begin(cmd, "composite");
  if (plan.linear) {
    // Blended onto the terrain pass's colour: order its writes before the
    // blend's reads.
    transitionImage(cmd, targets.hdr, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    VkRenderingAttachmentInfo hdr = colorAttachment(targets.hdr, false);
    hdr.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    beginRendering(cmd, plan.extent, &hdr, 1, nullptr);
    pass.pipelines.composite.bind(cmd, composite, nullptr);
  } else {
    // Read with the rest and written as display values: the tone map folded in.
    transitionImage(cmd, targets.hdr, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    const VkRenderingAttachmentInfo display = displayAttachment(plan, targets);
    beginRendering(cmd, plan.extent, &display, 1, nullptr);
    pass.pipelines.compositeDisplay(plan.mode).bind(
        cmd, composite.image(3, targets.hdr.view(), nearest), nullptr);
  }
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  pass.timer.end(cmd);
}

}  // namespace aal
