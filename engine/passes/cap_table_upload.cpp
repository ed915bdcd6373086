#include "aperture/engine/passes/frame_passes.h"

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/image.h"
#include "aperture/shaders/config.h"

namespace aal {

void recordCapTableUpload(VkCommandBuffer cmd, const Buffer& staging, const Image& table) {
  transitionImage(cmd, table, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  const VkBufferImageCopy region{
      .imageSubresource = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT,
                           .mipLevel = 0,
                           .baseArrayLayer = 0,
                           .layerCount = 1},
      .imageExtent = {.width = AAL_CAP_TABLE_WIDTH, .height = AAL_CAP_TABLE_HEIGHT, .depth = 1}};
  vkCmdCopyBufferToImage(cmd, staging.handle(), table.handle(),
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  transitionImage(cmd, table, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

}  // namespace aal
