#include "aperture/engine/passes/frame_passes.h"

#include "aperture/engine/vk/gpu_timer.h"

namespace aal {

void recordSkyTable(const PassContext& pass, const FrameTargets& targets) {
  transitionImage(pass.cmd, targets.skyTable, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  const VkRenderingAttachmentInfo table = colorAttachment(targets.skyTable, false);
  drawFullscreen(pass, "sky table", {AAL_SKY_LUT_WIDTH, AAL_SKY_LUT_HEIGHT}, &table, 1,
                 pass.pipelines.skyTable, DescriptorWrites().buffer(0, pass.uniforms));
  transitionImage(pass.cmd, targets.skyTable, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

void drawSky(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets) {
  pass.timer.begin(pass.cmd, "sky");
  // With the G-buffer in the same rendering it writes only the colour.
  pass.pipelines.sky(plan.mode, plan.direct, plan.obscurance && !plan.skyApart)
      .bind(pass.cmd,
            DescriptorWrites()
                .buffer(0, pass.uniforms)
                .image(1, targets.skyTable.view(), pass.pipelines.skySampler.handle()),
            nullptr);
  vkCmdDraw(pass.cmd, 3, 1, 0, 0);
  pass.timer.end(pass.cmd);
}

}  // namespace aal
