#include "aperture/engine/passes/frame_passes.h"

#include "aperture/engine/vk/gpu_timer.h"

namespace aal {

namespace {

// Scales the frame's smaller picture up into the output image (dynamic
// resolution, shaders/upscale.frag).
void recordUpscale(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets) {
  transitionImage(pass.cmd, targets.display, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(pass.cmd, plan.outputImage, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  VkRenderingAttachmentInfo target = colorAttachment(targets.display, false);
  target.imageView = plan.outputView;
  drawFullscreen(pass, "upscale", plan.fullExtent, &target, 1, pass.pipelines.upscale,
                 DescriptorWrites()
                     .buffer(0, pass.uniforms)
                     .image(1, targets.display.view(), pass.pipelines.linear.handle()));
  transitionImage(pass.cmd, targets.display, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                  VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

// The resolve pass of shaders/resolve.glsl: the history it reads (the last
// frame's, or none) sampled, the one it writes drawn into with `outputs`
// (the first of which the caller set); `drawn` is the picture of this frame,
// already in VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL. Leaves the depth
// sampled and the written history a colour attachment; returns it.
const Image& recordResolvePass(const PassContext& pass, const FramePlan& plan,
                               const FrameTargets& targets, const char* name,
                               const GraphicsPipeline& pipeline, const Image& drawn,
                               VkSampler drawnSampler, VkExtent2D extent,
                               VkRenderingAttachmentInfo* outputs, uint32_t outputCount) {
  const VkCommandBuffer cmd = pass.cmd;
  const Image& read = *targets.resolveHistory[plan.resolveRead];
  const Image& write = *targets.resolveHistory[1 - plan.resolveRead];
  transitionImage(cmd, targets.depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  // The last frame's history was left ready to be read; without one the
  // image holds nothing the shader reads, but it must be in a layout to bind.
  if (plan.resolveConstants.historyValid == 0) {
    transitionImage(cmd, read, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  }
  transitionImage(cmd, write, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  outputs[outputCount - 1] = colorAttachment(write, false);
  pass.timer.begin(cmd, name);
  beginRendering(cmd, extent, outputs, outputCount, nullptr);
  pipeline.bind(cmd,
                DescriptorWrites()
                    .buffer(0, pass.uniforms)
                    .image(1, drawn.view(), drawnSampler)
                    .image(2, targets.depth.view(), pass.pipelines.nearest.handle())
                    .image(3, read.view(), pass.pipelines.linear.handle()),
                &plan.resolveConstants);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  pass.timer.end(cmd);
  return write;
}

// Rebuilds the full-resolution picture from the smaller one and the last
// rebuilt frame into the output image and the history (temporal
// reconstruction).
void recordResolve(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets) {
  const VkCommandBuffer cmd = pass.cmd;
  transitionImage(cmd, targets.display, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, plan.outputImage, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  VkRenderingAttachmentInfo outputs[2] = {colorAttachment(targets.display, false), {}};
  outputs[0].imageView = plan.outputView;
  const Image& write =
      recordResolvePass(pass, plan, targets, "resolve", pass.pipelines.resolve, targets.display,
                        pass.pipelines.linear.handle(), plan.fullExtent, outputs, 2);
  transitionImage(cmd, write, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, targets.display, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                  VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

}  // namespace

void recordAccumulation(const PassContext& pass, const FramePlan& plan,
                        const FrameTargets& targets) {
  const VkCommandBuffer cmd = pass.cmd;
  transitionImage(cmd, targets.hdr, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  VkRenderingAttachmentInfo kept{};
  const Image& write =
      recordResolvePass(pass, plan, targets, "accumulate", pass.pipelines.resolveLinear,
                        targets.hdr, pass.pipelines.nearest.handle(), plan.extent, &kept, 1);
  // The accumulated frame is the frame: into the HDR target, which the tone
  // map and the linear read-back take as they would the drawn one.
  transitionImage(cmd, write, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  transitionImage(cmd, targets.hdr, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                  VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  const VkImageSubresourceLayers layers{
      .aspectMask = VK_IMAGE_ASPECT_COLOR_BIT, .mipLevel = 0, .baseArrayLayer = 0, .layerCount = 1};
  const VkImageCopy region{.srcSubresource = layers,
                           .dstSubresource = layers,
                           .extent = {plan.extent.width, plan.extent.height, 1}};
  vkCmdCopyImage(cmd, write.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, targets.hdr.handle(),
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  transitionImage(cmd, write, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, targets.hdr, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
}

void recordToneMap(const PassContext& pass, const FramePlan& plan, const FrameTargets& targets) {
  const VkCommandBuffer cmd = pass.cmd;
  transitionImage(cmd, targets.hdr, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  const VkRenderingAttachmentInfo display = displayAttachment(plan, targets);
  beginRendering(cmd, plan.extent, &display, 1, nullptr);
  pass.timer.begin(cmd, "tone map");
  pass.pipelines.toneMap.bind(cmd,
                              DescriptorWrites()
                                  .buffer(0, pass.uniforms)
                                  .image(1, targets.hdr.view(), pass.pipelines.nearest.handle()),
                              nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  pass.timer.end(cmd);
  vkCmdEndRendering(cmd);
}

void recordDisplayHandoff(const PassContext& pass, const FramePlan& plan,
                          const FrameTargets& targets) {
  // The display image ends ready to be copied (or read by the upscale).
  if (!plan.intoOutput) {
    transitionImage(pass.cmd, targets.display, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  }
  if (plan.resolve && !plan.linear) {
    recordResolve(pass, plan, targets);
  } else if (plan.upscale) {
    recordUpscale(pass, plan, targets);
  }
}

}  // namespace aal
