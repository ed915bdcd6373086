#include "aperture/engine/vk/image.h"

#include <string>
#include <utility>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

Image::Image(const Device& device, const ImageDesc& desc) : device_(device.handle()), desc_(desc) {
  const uint32_t limit = device.properties().limits.maxImageDimension2D;
  if (desc.width == 0 || desc.height == 0 || desc.width > limit || desc.height > limit) {
    throw VulkanError("image of " + std::to_string(desc.width) + "x" + std::to_string(desc.height) +
                      " is outside the device's limits (1.." + std::to_string(limit) +
                      " per side)");
  }
  const VkImageCreateInfo info{.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
                               .imageType = VK_IMAGE_TYPE_2D,
                               .format = desc.format,
                               .extent = {.width = desc.width, .height = desc.height, .depth = 1},
                               .mipLevels = desc.mipLevels,
                               .arrayLayers = desc.layers,
                               .samples = VK_SAMPLE_COUNT_1_BIT,
                               .tiling = VK_IMAGE_TILING_OPTIMAL,
                               .usage = desc.usage,
                               .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED};
  AAL_VK_CHECK(vkCreateImage(device_, &info, nullptr, &image_));

  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(device_, image_, &requirements);
  const VkMemoryAllocateInfo alloc{
      .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
      .allocationSize = requirements.size,
      .memoryTypeIndex = findMemoryType(device.memoryProperties(), requirements.memoryTypeBits,
                                        VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)};
  AAL_VK_CHECK(vkAllocateMemory(device_, &alloc, nullptr, &memory_));
  AAL_VK_CHECK(vkBindImageMemory(device_, image_, memory_, 0));

  const VkImageViewCreateInfo viewInfo{
      .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
      .image = image_,
      .viewType = desc.arrayView ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D,
      .format = desc.format,
      .subresourceRange = {.aspectMask = desc.aspect,
                           .baseMipLevel = 0,
                           .levelCount = desc.mipLevels,
                           .baseArrayLayer = 0,
                           .layerCount = desc.layers}};
  AAL_VK_CHECK(vkCreateImageView(device_, &viewInfo, nullptr, &view_));
}

Image::~Image() {
  release();
}

Image::Image(Image&& other) noexcept {
  *this = std::move(other);
}

Image& Image::operator=(Image&& other) noexcept {
  if (this != &other) {
    release();
    device_ = std::exchange(other.device_, VK_NULL_HANDLE);
    image_ = std::exchange(other.image_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    view_ = std::exchange(other.view_, VK_NULL_HANDLE);
    desc_ = other.desc_;
  }
  return *this;
}

void Image::release() {
  if (device_ == VK_NULL_HANDLE) return;
  if (view_ != VK_NULL_HANDLE) vkDestroyImageView(device_, view_, nullptr);
  if (image_ != VK_NULL_HANDLE) vkDestroyImage(device_, image_, nullptr);
  if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

namespace {

struct LayoutUse {
  VkPipelineStageFlags2 stage;
  VkAccessFlags2 access;
};

LayoutUse useOf(VkImageLayout layout) {
  switch (layout) {
    case VK_IMAGE_LAYOUT_UNDEFINED: return {VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, 0};
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT};
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT};
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
                  VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
              VK_ACCESS_2_SHADER_SAMPLED_READ_BIT};
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
              VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT};
    case VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL:
      return {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT |
                  VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
              VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                  VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT};
    case VK_IMAGE_LAYOUT_PRESENT_SRC_KHR: return {VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, 0};
    default:
      return {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
              VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT};
  }
}

}  // namespace

namespace {

void transitionRange(VkCommandBuffer cmd, VkImage image, const VkImageSubresourceRange& range,
                     VkImageLayout from, VkImageLayout to) {
  LayoutUse src = useOf(from);
  const LayoutUse dst = useOf(to);
  // From UNDEFINED nothing is kept, but earlier work at the stage that comes
  // next must be done (last frame's use of the image) and, for a swapchain
  // image, the acquire semaphore waited for at that stage chains to it.
  if (from == VK_IMAGE_LAYOUT_UNDEFINED) src.stage = dst.stage;
  const VkImageMemoryBarrier2 barrier{.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
                                      .srcStageMask = src.stage,
                                      .srcAccessMask = src.access,
                                      .dstStageMask = dst.stage,
                                      .dstAccessMask = dst.access,
                                      .oldLayout = from,
                                      .newLayout = to,
                                      .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                      .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                      .image = image,
                                      .subresourceRange = range};
  const VkDependencyInfo dependency{.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                    .imageMemoryBarrierCount = 1,
                                    .pImageMemoryBarriers = &barrier};
  vkCmdPipelineBarrier2(cmd, &dependency);
}

}  // namespace

void transitionImage(VkCommandBuffer cmd, const Image& image, VkImageLayout from,
                     VkImageLayout to) {
  transitionRange(cmd, image.handle(),
                  {.aspectMask = image.desc().aspect,
                   .baseMipLevel = 0,
                   .levelCount = image.desc().mipLevels,
                   .baseArrayLayer = 0,
                   .layerCount = image.desc().layers},
                  from, to);
}

void transitionImage(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to) {
  transitionRange(cmd, image,
                  {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT,
                   .baseMipLevel = 0,
                   .levelCount = 1,
                   .baseArrayLayer = 0,
                   .layerCount = 1},
                  from, to);
}

void copyImageToBuffer(VkCommandBuffer cmd, const Image& image, const Buffer& buffer) {
  const VkBufferImageCopy region{
      .imageSubresource = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT,
                           .mipLevel = 0,
                           .baseArrayLayer = 0,
                           .layerCount = 1},
      .imageExtent = {.width = image.desc().width, .height = image.desc().height, .depth = 1}};
  vkCmdCopyImageToBuffer(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.handle(),
                         1, &region);
}

}  // namespace aal
