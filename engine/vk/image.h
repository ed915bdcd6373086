// 2D images (textures and render targets) with their memory and a view.
#pragma once

#include <vulkan/vulkan.h>

namespace aal {

class Device;

struct ImageDesc {
  uint32_t width = 0, height = 0;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkImageUsageFlags usage = 0;
  VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
  // Array layers; with arrayView the view is a 2D array (sampler2DArray)
  // even for one layer.
  uint32_t layers = 1;
  bool arrayView = false;
  // Mip levels; the view covers them all.
  uint32_t mipLevels = 1;
};

class Image {
 public:
  Image() = default;
  // Device-local image; throws VulkanError naming the limit when the size is
  // beyond the device's maxImageDimension2D.
  Image(const Device& device, const ImageDesc& desc);
  ~Image();
  Image(Image&& other) noexcept;
  Image& operator=(Image&& other) noexcept;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  const ImageDesc& desc() const { return desc_; }
  VkExtent2D extent() const { return {desc_.width, desc_.height}; }

 private:
  void release();

  VkDevice device_ = VK_NULL_HANDLE;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  ImageDesc desc_;
};

class Buffer;

// Records a copy of the whole image (colour aspect, in
// VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) into `buffer`, tightly packed.
void copyImageToBuffer(VkCommandBuffer cmd, const Image& image, const Buffer& buffer);

// Records a layout transition of the whole image, every layer and level
// (synchronization2), with conservative stage/access masks derived from the layouts.
void transitionImage(VkCommandBuffer cmd, const Image& image, VkImageLayout from, VkImageLayout to);
// The same for an image not made here (a swapchain image): one colour level
// and layer.
void transitionImage(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to);

}  // namespace aal
