// The window's swapchain: images in a UNORM format (the renderer's display
// image already holds sRGB-encoded values, so they must not be encoded
// twice), FIFO with vsync or MAILBOX/IMMEDIATE without, and recreation when
// the window changes.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

class Device;

enum class SwapchainStatus {
  Ok,           // acquired or presented (acquire: possibly suboptimal; present reports that)
  OutOfDate,    // out of date or suboptimal: recreate the swapchain
  SurfaceLost,  // the window surface is gone: recreate the surface, then the swapchain
};

class Swapchain {
 public:
  // Throws VulkanError when the device's queue cannot present to `surface`
  // or no UNORM 8-bit format that can be blitted to exists.
  Swapchain(const Device& device, VkSurfaceKHR surface, VkExtent2D framebuffer, bool vsync);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // Rebuilds for a new framebuffer size or vsync setting (the device must be
  // idle). The extent follows the surface when it dictates one.
  void recreate(VkExtent2D framebuffer, bool vsync);

  // Rebuilds on a new surface after the old one was lost.
  void recreate(VkSurfaceKHR surface, VkExtent2D framebuffer, bool vsync);

  // Acquires the next image, signalling `acquired` when it may be written.
  // Ok includes a suboptimal image (drawn and presented, then recreated).
  SwapchainStatus acquire(VkSemaphore acquired, uint32_t* imageIndex);
  // Presents `imageIndex` after `rendered` is signalled.
  SwapchainStatus present(uint32_t imageIndex, VkSemaphore rendered);

  VkFormat format() const { return format_; }
  VkExtent2D extent() const { return extent_; }
  VkPresentModeKHR presentMode() const { return presentMode_; }
  uint32_t minImageCount() const { return minImageCount_; }
  uint32_t imageCount() const { return static_cast<uint32_t>(images_.size()); }
  VkImage image(uint32_t index) const { return images_[index]; }
  // True when the images can be copied from (VK_IMAGE_USAGE_TRANSFER_SRC_BIT).
  bool readable() const { return readable_; }
  VkImageView view(uint32_t index) const { return views_[index]; }

 private:
  void create(VkExtent2D framebuffer, bool vsync);
  void destroyViews();

  const Device& device_;
  VkSurfaceKHR surface_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkColorSpaceKHR colorSpace_ = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
  VkExtent2D extent_{0, 0};
  VkPresentModeKHR presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
  uint32_t minImageCount_ = 2;
  bool readable_ = false;
  std::vector<VkImage> images_;
  std::vector<VkImageView> views_;
};

}  // namespace aal
