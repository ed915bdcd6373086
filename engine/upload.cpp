#include "upload.h"

#include <stdexcept>

#include "buffer.h"
#include "commands.h"
#include "device.h"
#include "image.h"

namespace aal {

namespace {
size_t alignUp(size_t value, size_t alignment) {
  return (value + alignment - 1) / alignment * alignment;
}
}  // namespace

void UploadBatch::add(const Image* image, const Buffer* buffer, const void* data, size_t bytes) {
  const size_t offset = alignUp(stagingBytes_, 16);
  stagingBytes_ = offset + bytes;
  pending_.push_back({image, buffer, data, offset, bytes});
}

void UploadBatch::addImage(const Image& image, const void* data, size_t bytes) {
  add(&image, nullptr, data, bytes);
}

void UploadBatch::addBuffer(const Buffer& buffer, const void* data, size_t bytes) {
  if (bytes > buffer.size()) throw std::logic_error("UploadBatch::addBuffer: too many bytes");
  add(nullptr, &buffer, data, bytes);
}

void UploadBatch::submit() {
  if (pending_.empty()) return;
  Buffer staging(device_, stagingBytes_, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryIntent::Upload);
  for (const Pending& p : pending_) staging.write(p.data, p.bytes, p.offset);
  submitAndWait(device_, [&](VkCommandBuffer cmd) {
    for (const Pending& p : pending_) {
      if (p.buffer) {
        VkBufferCopy region{p.offset, 0, p.bytes};
        vkCmdCopyBuffer(cmd, staging.handle(), p.buffer->handle(), 1, &region);
        continue;
      }
      transitionImage(cmd, *p.image, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
      VkBufferImageCopy region{};
      region.bufferOffset = p.offset;
      region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      region.imageExtent = {p.image->desc().width, p.image->desc().height, 1};
      vkCmdCopyBufferToImage(cmd, staging.handle(), p.image->handle(),
                             VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
      transitionImage(cmd, *p.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    // Buffer copies must be visible to vertex input and shaders.
    VkMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    barrier.srcStageMask = VK_PIPELINE_STAGE_2_TRANSFER_BIT;
    barrier.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    barrier.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    barrier.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT;
    VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dependency.memoryBarrierCount = 1;
    dependency.pMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dependency);
  });
  stagingBytes_ = 0;
  pending_.clear();
}

}  // namespace aal
