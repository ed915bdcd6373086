// Dear ImGui on top of the presented frame. Debian's imgui 1.86 Vulkan
// backend draws inside a classic VkRenderPass, so the overlay owns one
// (load the blitted frame, draw the UI, leave the image ready to present)
// and a framebuffer per swapchain image.
#pragma once

#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

class Device;
class Instance;
class Swapchain;
class Window;

class UiOverlay {
 public:
  // Creates the ImGui context with the GLFW and Vulkan backends, uploads
  // the font (scaled by the window's content scale for high-DPI screens).
  // The GLFW backend's callbacks feed ImGui keys, characters and the wheel;
  // the window's size, the cursor and the buttons are fed each frame from
  // the state `window` keeps (beginFrame).
  UiOverlay(const Instance& instance, const Device& device, Window& window,
            const Swapchain& swapchain);
  ~UiOverlay();
  UiOverlay(const UiOverlay&) = delete;
  UiOverlay& operator=(const UiOverlay&) = delete;

  // After the swapchain was recreated (device idle): new framebuffers.
  void onSwapchainRecreated(const Swapchain& swapchain);

  // Starts a UI frame: ImGui widgets may be issued until record(). Asks
  // the X server nothing: the GLFW backend's own start of a frame would ask
  // it the window's size twice, its focus and the cursor, and each round
  // trip waits for the server to finish copying the last frame's picture
  // (docs/performance.md, "Where a frame's time goes").
  void beginFrame();
  // Finishes the UI frame and records the UI render pass into swapchain
  // image `imageIndex`, which must be in COLOR_ATTACHMENT_OPTIMAL; leaves it
  // in PRESENT_SRC_KHR.
  void record(VkCommandBuffer cmd, uint32_t imageIndex);

  // True while the mouse or keyboard is over/used by a UI widget (the
  // camera ignores them then).
  bool wantsMouse() const;
  bool wantsKeyboard() const;

 private:
  void createFramebuffers(const Swapchain& swapchain);
  void destroyFramebuffers();

  const Device& device_;
  Window& window_;
  double lastFrameS_ = 0;
  VkRenderPass renderPass_ = VK_NULL_HANDLE;
  VkDescriptorPool descriptorPool_ = VK_NULL_HANDLE;
  std::vector<VkFramebuffer> framebuffers_;
  VkExtent2D extent_{0, 0};
  bool frameStarted_ = false;
};

}  // namespace aal
