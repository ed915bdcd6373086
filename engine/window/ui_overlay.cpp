#include "aperture/engine/window/ui_overlay.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include <algorithm>
#include <cfloat>

#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/frames_in_flight.h"
#include "aperture/engine/vk/instance.h"
#include "aperture/engine/vk/vk_check.h"
#include "aperture/engine/window/swapchain.h"
#include "aperture/engine/window/window.h"

namespace aal {

namespace {

void checkImGuiVkResult(VkResult result) {
  if (result != VK_SUCCESS) throwVkFailure(result, "imgui vulkan backend", __FILE__, __LINE__);
}

VkRenderPass makeRenderPass(VkDevice device, VkFormat format) {
  const VkAttachmentDescription color{
      .format = format,
      .samples = VK_SAMPLE_COUNT_1_BIT,
      .loadOp = VK_ATTACHMENT_LOAD_OP_LOAD,  // the terrain frame drawn before
      .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
      .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
      .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
      .initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
      .finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR};
  const VkAttachmentReference ref{.attachment = 0,
                                  .layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  const VkSubpassDescription subpass{.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
                                     .colorAttachmentCount = 1,
                                     .pColorAttachments = &ref};
  // The caller's barrier made the image a colour attachment; order the
  // load after it.
  const VkSubpassDependency dependency{
      .srcSubpass = VK_SUBPASS_EXTERNAL,
      .dstSubpass = 0,
      .srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
      .dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
      .srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
      .dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT};
  const VkRenderPassCreateInfo info{.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
                                    .attachmentCount = 1,
                                    .pAttachments = &color,
                                    .subpassCount = 1,
                                    .pSubpasses = &subpass,
                                    .dependencyCount = 1,
                                    .pDependencies = &dependency};
  VkRenderPass pass = VK_NULL_HANDLE;
  AAL_VK_CHECK(vkCreateRenderPass(device, &info, nullptr, &pass));
  return pass;
}

VkDescriptorPool makeDescriptorPool(VkDevice device) {
  // The backend needs one combined image sampler (the font).
  const VkDescriptorPoolSize size{.type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                  .descriptorCount = 4};
  const VkDescriptorPoolCreateInfo info{.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                        .flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT,
                                        .maxSets = 4,
                                        .poolSizeCount = 1,
                                        .pPoolSizes = &size};
  VkDescriptorPool pool = VK_NULL_HANDLE;
  AAL_VK_CHECK(vkCreateDescriptorPool(device, &info, nullptr, &pool));
  return pool;
}

}  // namespace

UiOverlay::UiOverlay(const Instance& instance, const Device& device, Window& window,
                     const Swapchain& swapchain)
    : device_(device), window_(window) {
  renderPass_ = makeRenderPass(device.handle(), swapchain.format());
  descriptorPool_ = makeDescriptorPool(device.handle());

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini in the user's folder
  // The cursor's shape is the backend's, left out with its start of a frame.
  io.ConfigFlags |= ImGuiConfigFlags_NoMouseCursorChange;
  const float scale = window.contentScale();
  ImFontConfig font;
  font.SizePixels = 13.0f * scale;
  io.Fonts->AddFontDefault(&font);
  ImGui::StyleColorsDark();
  ImGui::GetStyle().ScaleAllSizes(scale);

  ImGui_ImplGlfw_InitForVulkan(window.handle(), true);
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = instance.handle();
  info.PhysicalDevice = device.physical();
  info.Device = device.handle();
  info.QueueFamily = device.queueFamily();
  info.Queue = device.queue();
  info.DescriptorPool = descriptorPool_;
  info.Subpass = 0;
  info.MinImageCount = swapchain.minImageCount();
  // ImGui's vertex buffers, written by the host each frame, rotate over
  // ImageCount copies: at least one per frame in flight.
  info.ImageCount = std::max(swapchain.imageCount(), kFramesInFlight);
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = checkImGuiVkResult;
  ImGui_ImplVulkan_Init(&info, renderPass_);
  submitAndWait(device, [](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
  createFramebuffers(swapchain);
}

UiOverlay::~UiOverlay() {
  vkDeviceWaitIdle(device_.handle());
  if (frameStarted_) ImGui::EndFrame();
  destroyFramebuffers();
  ImGui_ImplVulkan_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  vkDestroyDescriptorPool(device_.handle(), descriptorPool_, nullptr);
  vkDestroyRenderPass(device_.handle(), renderPass_, nullptr);
}

void UiOverlay::createFramebuffers(const Swapchain& swapchain) {
  extent_ = swapchain.extent();
  for (uint32_t i = 0; i < swapchain.imageCount(); ++i) {
    const VkImageView view = swapchain.view(i);
    const VkFramebufferCreateInfo info{.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
                                       .renderPass = renderPass_,
                                       .attachmentCount = 1,
                                       .pAttachments = &view,
                                       .width = extent_.width,
                                       .height = extent_.height,
                                       .layers = 1};
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    AAL_VK_CHECK(vkCreateFramebuffer(device_.handle(), &info, nullptr, &framebuffer));
    framebuffers_.push_back(framebuffer);
  }
}

void UiOverlay::destroyFramebuffers() {
  for (VkFramebuffer f : framebuffers_) vkDestroyFramebuffer(device_.handle(), f, nullptr);
  framebuffers_.clear();
}

void UiOverlay::onSwapchainRecreated(const Swapchain& swapchain) {
  destroyFramebuffers();
  ImGui_ImplVulkan_SetMinImageCount(swapchain.minImageCount());
  createFramebuffers(swapchain);
}

void UiOverlay::beginFrame() {
  if (frameStarted_) ImGui::EndFrame();  // the last frame was skipped (swapchain recreated)
  ImGui_ImplVulkan_NewFrame();
  ImGuiIO& io = ImGui::GetIO();
  const glm::ivec2 size = window_.size();
  const VkExtent2D framebuffer = window_.framebufferSize();
  io.DisplaySize = ImVec2(float(size.x), float(size.y));
  if (size.x > 0 && size.y > 0) {
    io.DisplayFramebufferScale =
        ImVec2(float(framebuffer.width) / float(size.x), float(framebuffer.height) / float(size.y));
  }
  const double now = glfwGetTime();
  io.DeltaTime = lastFrameS_ > 0 && now > lastFrameS_ ? float(now - lastFrameS_) : 1.0f / 60.0f;
  lastFrameS_ = now;
  // A press since the last frame counts as held, so a click shorter than a
  // frame is not lost.
  const unsigned pressed = window_.takeButtonPresses();
  for (int b = 0; b < IM_ARRAYSIZE(io.MouseDown); ++b) {
    io.MouseDown[b] = (pressed >> b & 1u) != 0 || window_.mouseButtonDown(b);
  }
  const glm::dvec2 cursor = window_.cursorPosition();
  io.MousePos =
      window_.focused() ? ImVec2(float(cursor.x), float(cursor.y)) : ImVec2(-FLT_MAX, -FLT_MAX);
  ImGui::NewFrame();
  frameStarted_ = true;
}

void UiOverlay::record(VkCommandBuffer cmd, uint32_t imageIndex) {
  ImGui::Render();
  frameStarted_ = false;
  const VkRenderPassBeginInfo begin{.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
                                    .renderPass = renderPass_,
                                    .framebuffer = framebuffers_[imageIndex],
                                    .renderArea = {.offset = {0, 0}, .extent = extent_}};
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
  vkCmdEndRenderPass(cmd);
}

bool UiOverlay::wantsMouse() const {
  return ImGui::GetIO().WantCaptureMouse;
}
bool UiOverlay::wantsKeyboard() const {
  return ImGui::GetIO().WantCaptureKeyboard;
}

}  // namespace aal
