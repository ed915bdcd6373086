#include "aperture/engine/vk/upload.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/image.h"

namespace aal {

struct UploadCopy {
  const Image* image = nullptr;
  const Buffer* buffer = nullptr;
  size_t stagingOffset = 0, bytes = 0;
  uint32_t firstRow = 0, rows = 0, layer = 0, level = 0;
  size_t bufferOffset = 0;
  bool first = false, last = false;  // the image's first and last band: its transitions
};

namespace {

size_t alignUp(size_t value, size_t alignment) {
  return (value + alignment - 1) / alignment * alignment;
}

// Rows of level 0 that make whole rows of every level of `image`.
uint32_t rowsPerBandStep(const Image& image) {
  return 1u << (image.desc().mipLevels - 1);
}

// Staging bytes of `rows` level-0 rows and their rows of the other levels
// (rows a multiple of rowsPerBandStep).
size_t bandBytes(const Image& image, size_t bytesPerTexel, uint32_t rows) {
  size_t bytes = 0;
  for (uint32_t level = 0; level < image.desc().mipLevels; ++level) {
    bytes += alignUp(size_t{image.desc().width >> level} * bytesPerTexel * (rows >> level), 16);
  }
  return bytes;
}

// The copies of one staging-buffer load, with the images' transitions.
void recordCopies(VkCommandBuffer cmd, const Buffer& staging,
                  const std::vector<UploadCopy>& copies) {
  for (const UploadCopy& c : copies) {
    if (c.buffer) {
      const VkBufferCopy region{
          .srcOffset = c.stagingOffset, .dstOffset = c.bufferOffset, .size = c.bytes};
      vkCmdCopyBuffer(cmd, staging.handle(), c.buffer->handle(), 1, &region);
      continue;
    }
    // Bands after the first find the image already in TRANSFER_DST.
    if (c.first) {
      transitionImage(cmd, *c.image, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    }
    const VkBufferImageCopy region{
        .bufferOffset = c.stagingOffset,
        .imageSubresource = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT,
                             .mipLevel = c.level,
                             .baseArrayLayer = c.layer,
                             .layerCount = 1},
        .imageOffset = {.x = 0, .y = static_cast<int32_t>(c.firstRow), .z = 0},
        .imageExtent = {.width = c.image->desc().width >> c.level, .height = c.rows, .depth = 1}};
    vkCmdCopyBufferToImage(cmd, staging.handle(), c.image->handle(),
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    if (c.last) {
      transitionImage(cmd, *c.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
  }
  // Buffer copies must be visible to vertex input and shaders.
  const VkMemoryBarrier2 barrier{.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                                 .srcStageMask = VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                                 .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                 .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                 .dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT};
  const VkDependencyInfo dependency{.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                    .memoryBarrierCount = 1,
                                    .pMemoryBarriers = &barrier};
  vkCmdPipelineBarrier2(cmd, &dependency);
}

}  // namespace

void UploadBatch::addImage(const Image& image, size_t bytesPerTexel, RowWriter rows, uint32_t layer,
                           MipReducer reduce) {
  if (layer >= image.desc().layers) throw std::logic_error("UploadBatch::addImage: no such layer");
  const uint32_t step = rowsPerBandStep(image);
  if (step > 1 && (!reduce || image.desc().width % step || image.desc().height % step)) {
    throw std::logic_error("UploadBatch::addImage: mip levels need a reducer and aligned sizes");
  }
  Pending p;
  p.image = &image;
  p.bytesPerTexel = bytesPerTexel;
  p.rows = std::move(rows);
  p.layer = layer;
  p.reduce = reduce;
  pending_.push_back(std::move(p));
}

void UploadBatch::addImage(const Image& image, size_t bytesPerTexel, const void* data) {
  const size_t rowBytes = image.desc().width * bytesPerTexel;
  const auto* bytes = static_cast<const unsigned char*>(data);
  addImage(image, bytesPerTexel, [bytes, rowBytes](uint32_t first, uint32_t end, void* dst) {
    std::memcpy(dst, bytes + first * rowBytes, (end - first) * rowBytes);
  });
}

void UploadBatch::addBuffer(const Buffer& buffer, const void* data, size_t bytes) {
  if (bytes > buffer.size()) throw std::logic_error("UploadBatch::addBuffer: too many bytes");
  Pending p;
  p.buffer = &buffer;
  p.data = static_cast<const unsigned char*>(data);
  p.bytes = bytes;
  pending_.push_back(std::move(p));
}

void UploadBatch::submit() {
  transfer(stagingLimit_, VK_NULL_HANDLE);
}

void UploadBatch::record(VkCommandBuffer cmd) {
  transfer(std::numeric_limits<size_t>::max(), cmd);
}

size_t UploadBatch::bytesLeft() const {
  size_t left = 0;
  for (size_t i = next_; i < pending_.size(); ++i) {
    const Pending& p = pending_[i];
    if (p.image) {
      left += bandBytes(*p.image, p.bytesPerTexel, p.image->desc().height) -
              bandBytes(*p.image, p.bytesPerTexel, static_cast<uint32_t>(p.done));
    } else {
      left += alignUp(p.bytes - p.done, 16);
    }
  }
  return left;
}

size_t UploadBatch::loadCapacity(size_t limit) const {
  size_t widestBand = 16;
  for (size_t i = next_; i < pending_.size(); ++i) {
    const Pending& p = pending_[i];
    if (p.image) {
      widestBand =
          std::max(widestBand, bandBytes(*p.image, p.bytesPerTexel, rowsPerBandStep(*p.image)));
    }
  }
  return std::max(std::min(bytesLeft(), limit), widestBand);
}

std::vector<UploadCopy> UploadBatch::fill(unsigned char* mapped, size_t capacity) {
  std::vector<UploadCopy> copies;
  size_t used = 0;
  for (; next_ < pending_.size(); ++next_) {
    Pending& p = pending_[next_];
    if (p.image) {
      const ImageDesc& d = p.image->desc();
      const uint32_t step = rowsPerBandStep(*p.image);
      // As many whole steps of rows as fit.
      uint32_t rows = 0;
      while (p.done + rows < d.height &&
             bandBytes(*p.image, p.bytesPerTexel, rows + step) <= capacity - used) {
        rows += step;
      }
      if (rows == 0) break;
      const uint32_t first = static_cast<uint32_t>(p.done);
      const unsigned char* upper = nullptr;
      for (uint32_t level = 0; level < d.mipLevels; ++level) {
        const uint32_t width = d.width >> level, levelRows = rows >> level;
        const size_t rowBytes = size_t{width} * p.bytesPerTexel;
        unsigned char* out = mapped + used;
        if (level == 0) {
          p.rows(first, first + rows, out);
        } else {
          // From the level above, just written to the staging buffer.
          for (uint32_t r = 0; r < levelRows; ++r) {
            p.reduce(upper + 2 * r * 2 * rowBytes, upper + (2 * r + 1) * 2 * rowBytes,
                     out + r * rowBytes, width);
          }
        }
        upper = out;
        // The image's layout changes with its first layer's first band and
        // after its last layer's last band (the transitions cover every
        // layer and level).
        copies.push_back({.image = p.image,
                          .stagingOffset = used,
                          .bytes = levelRows * rowBytes,
                          .firstRow = first >> level,
                          .rows = levelRows,
                          .layer = p.layer,
                          .level = level,
                          .first = first == 0 && p.layer == 0 && level == 0,
                          .last = first + rows == d.height && p.layer + 1 == d.layers &&
                                  level + 1 == d.mipLevels});
        used = alignUp(used + levelRows * rowBytes, 16);
      }
      p.done += rows;
      if (p.done < d.height) break;
    } else {
      const size_t chunk = std::min(capacity - used, p.bytes - p.done);
      if (chunk == 0) break;
      std::memcpy(mapped + used, p.data + p.done, chunk);
      copies.push_back(
          {.buffer = p.buffer, .stagingOffset = used, .bytes = chunk, .bufferOffset = p.done});
      used = alignUp(used + chunk, 16);
      p.done += chunk;
      if (p.done < p.bytes) break;
    }
  }
  return copies;
}

void UploadBatch::transfer(size_t limit, VkCommandBuffer cmd) {
  if (next_ >= pending_.size()) {
    pending_.clear();
    next_ = 0;
    return;
  }
  const size_t capacity = loadCapacity(limit);
  Buffer staging(device_, capacity, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryIntent::Upload);
  for (size_t loads = 0; next_ < pending_.size(); ++loads) {
    // Recorded, a load's copies run later: the next load takes a buffer of
    // its own (the bands' alignment can make everything one load too many).
    if (cmd != VK_NULL_HANDLE && loads > 0) {
      device_.deletionQueue().retire(std::exchange(
          staging,
          Buffer(device_, capacity, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryIntent::Upload)));
    }
    const std::vector<UploadCopy> copies =
        fill(static_cast<unsigned char*>(staging.mapped()), capacity);
    staging.flush();
    if (cmd != VK_NULL_HANDLE) {
      recordCopies(cmd, staging, copies);
    } else {
      submitAndWait(device_, [&](VkCommandBuffer one) { recordCopies(one, staging, copies); });
    }
  }
  pending_.clear();
  next_ = 0;
  if (cmd != VK_NULL_HANDLE) device_.deletionQueue().retire(std::move(staging));
}

bool UploadBatch::recordShare(VkCommandBuffer cmd, size_t bytes) {
  if (next_ < pending_.size()) {
    const size_t capacity = loadCapacity(bytes);
    Buffer staging(device_, capacity, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryIntent::Upload);
    const std::vector<UploadCopy> copies =
        fill(static_cast<unsigned char*>(staging.mapped()), capacity);
    staging.flush();
    recordCopies(cmd, staging, copies);
    device_.deletionQueue().retire(std::move(staging));
  }
  if (next_ < pending_.size()) return false;
  pending_.clear();
  next_ = 0;
  return true;
}

}  // namespace aal
