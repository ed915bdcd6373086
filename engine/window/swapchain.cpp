#include "aperture/engine/window/swapchain.h"

#include <algorithm>

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

namespace {

constexpr VkFormatFeatureFlags kNeededFeatures =
    VK_FORMAT_FEATURE_BLIT_DST_BIT | VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT;

VkSurfaceFormatKHR chooseFormat(const Device& device, VkSurfaceKHR surface) {
  uint32_t count = 0;
  AAL_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(device.physical(), surface, &count, nullptr));
  std::vector<VkSurfaceFormatKHR> formats(count);
  AAL_VK_CHECK(
      vkGetPhysicalDeviceSurfaceFormatsKHR(device.physical(), surface, &count, formats.data()));
  for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM}) {
    VkFormatProperties props;
    vkGetPhysicalDeviceFormatProperties(device.physical(), wanted, &props);
    if ((props.optimalTilingFeatures & kNeededFeatures) != kNeededFeatures) continue;
    for (const VkSurfaceFormatKHR& f : formats) {
      if (f.format == wanted && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
    }
  }
  throw VulkanError(
      "the window surface offers no B8G8R8A8_UNORM or R8G8B8A8_UNORM format that can be blitted "
      "to");
}

VkPresentModeKHR choosePresentMode(const Device& device, VkSurfaceKHR surface, bool vsync) {
  if (vsync) return VK_PRESENT_MODE_FIFO_KHR;  // always available
  uint32_t count = 0;
  AAL_VK_CHECK(
      vkGetPhysicalDeviceSurfacePresentModesKHR(device.physical(), surface, &count, nullptr));
  std::vector<VkPresentModeKHR> modes(count);
  AAL_VK_CHECK(
      vkGetPhysicalDeviceSurfacePresentModesKHR(device.physical(), surface, &count, modes.data()));
  for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR}) {
    if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) return wanted;
  }
  return VK_PRESENT_MODE_FIFO_KHR;
}

}  // namespace

Swapchain::Swapchain(const Device& device, VkSurfaceKHR surface, VkExtent2D framebuffer, bool vsync)
    : device_(device), surface_(surface) {
  VkBool32 canPresent = VK_FALSE;
  AAL_VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(device.physical(), device.queueFamily(),
                                                    surface, &canPresent));
  if (!canPresent) {
    throw VulkanError("the Vulkan device " + device.name() +
                      " cannot present to this window; pick another with --device");
  }
  const VkSurfaceFormatKHR f = chooseFormat(device, surface);
  format_ = f.format;
  colorSpace_ = f.colorSpace;
  create(framebuffer, vsync);
}

Swapchain::~Swapchain() {
  destroyViews();
  if (swapchain_ != VK_NULL_HANDLE) vkDestroySwapchainKHR(device_.handle(), swapchain_, nullptr);
}

void Swapchain::destroyViews() {
  for (VkImageView view : views_) vkDestroyImageView(device_.handle(), view, nullptr);
  views_.clear();
  images_.clear();
}

void Swapchain::recreate(VkExtent2D framebuffer, bool vsync) {
  destroyViews();
  create(framebuffer, vsync);
}

void Swapchain::recreate(VkSurfaceKHR surface, VkExtent2D framebuffer, bool vsync) {
  // The old swapchain belongs to the lost surface: it cannot be retired into
  // the new one.
  destroyViews();
  if (swapchain_ != VK_NULL_HANDLE) vkDestroySwapchainKHR(device_.handle(), swapchain_, nullptr);
  swapchain_ = VK_NULL_HANDLE;
  surface_ = surface;
  create(framebuffer, vsync);
}

void Swapchain::create(VkExtent2D framebuffer, bool vsync) {
  VkSurfaceCapabilitiesKHR caps;
  AAL_VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(device_.physical(), surface_, &caps));
  // 0xFFFFFFFF: the surface takes the size of the swapchain.
  if (caps.currentExtent.width != UINT32_MAX) {
    extent_ = caps.currentExtent;
  } else {
    extent_ = {
        std::clamp(framebuffer.width, caps.minImageExtent.width, caps.maxImageExtent.width),
        std::clamp(framebuffer.height, caps.minImageExtent.height, caps.maxImageExtent.height)};
  }
  presentMode_ = choosePresentMode(device_, surface_, vsync);
  // One more than the minimum so that acquiring rarely waits for the
  // presentation engine; the UI needs at least two.
  minImageCount_ = std::max(2u, caps.minImageCount + 1);
  if (caps.maxImageCount != 0) minImageCount_ = std::min(minImageCount_, caps.maxImageCount);

  // Screenshots read back what is presented, where the surface allows it.
  readable_ = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;
  VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  if (readable_) usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  const VkSwapchainCreateInfoKHR info{
      .sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
      .surface = surface_,
      .minImageCount = minImageCount_,
      .imageFormat = format_,
      .imageColorSpace = colorSpace_,
      .imageExtent = extent_,
      .imageArrayLayers = 1,
      .imageUsage = usage,
      .imageSharingMode = VK_SHARING_MODE_EXCLUSIVE,
      .preTransform = caps.currentTransform,
      .compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                            ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                            : VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR,
      .presentMode = presentMode_,
      .clipped = VK_TRUE,
      .oldSwapchain = swapchain_};
  VkSwapchainKHR created = VK_NULL_HANDLE;
  AAL_VK_CHECK(vkCreateSwapchainKHR(device_.handle(), &info, nullptr, &created));
  if (swapchain_ != VK_NULL_HANDLE) vkDestroySwapchainKHR(device_.handle(), swapchain_, nullptr);
  swapchain_ = created;

  uint32_t count = 0;
  AAL_VK_CHECK(vkGetSwapchainImagesKHR(device_.handle(), swapchain_, &count, nullptr));
  images_.resize(count);
  AAL_VK_CHECK(vkGetSwapchainImagesKHR(device_.handle(), swapchain_, &count, images_.data()));
  for (VkImage image : images_) {
    const VkImageViewCreateInfo viewInfo{
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = image,
        .viewType = VK_IMAGE_VIEW_TYPE_2D,
        .format = format_,
        .subresourceRange = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT,
                             .baseMipLevel = 0,
                             .levelCount = 1,
                             .baseArrayLayer = 0,
                             .layerCount = 1}};
    VkImageView view = VK_NULL_HANDLE;
    AAL_VK_CHECK(vkCreateImageView(device_.handle(), &viewInfo, nullptr, &view));
    views_.push_back(view);
  }
}

SwapchainStatus Swapchain::acquire(VkSemaphore acquired, uint32_t* imageIndex) {
  const VkResult result = vkAcquireNextImageKHR(device_.handle(), swapchain_, UINT64_MAX, acquired,
                                                VK_NULL_HANDLE, imageIndex);
  if (result == VK_ERROR_OUT_OF_DATE_KHR) return SwapchainStatus::OutOfDate;
  if (result == VK_ERROR_SURFACE_LOST_KHR) return SwapchainStatus::SurfaceLost;
  if (result != VK_SUBOPTIMAL_KHR) AAL_VK_CHECK(result);
  return SwapchainStatus::Ok;
}

SwapchainStatus Swapchain::present(uint32_t imageIndex, VkSemaphore rendered) {
  const VkPresentInfoKHR info{.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
                              .waitSemaphoreCount = 1,
                              .pWaitSemaphores = &rendered,
                              .swapchainCount = 1,
                              .pSwapchains = &swapchain_,
                              .pImageIndices = &imageIndex};
  const VkResult result = vkQueuePresentKHR(device_.queue(), &info);
  if (result == VK_ERROR_OUT_OF_DATE_KHR || result == VK_SUBOPTIMAL_KHR) {
    return SwapchainStatus::OutOfDate;
  }
  if (result == VK_ERROR_SURFACE_LOST_KHR) return SwapchainStatus::SurfaceLost;
  AAL_VK_CHECK(result);
  return SwapchainStatus::Ok;
}

}  // namespace aal
