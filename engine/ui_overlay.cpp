#include "ui_overlay.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include "commands.h"
#include "device.h"
#include "instance.h"
#include "swapchain.h"
#include "vk_check.h"
#include "window.h"

namespace aal {

namespace {

void checkImGuiVkResult(VkResult result) {
  if (result != VK_SUCCESS) throwVkFailure(result, "imgui vulkan backend", __FILE__, __LINE__);
}

VkRenderPass makeRenderPass(VkDevice device, VkFormat format) {
  VkAttachmentDescription color{};
  color.format = format;
  color.samples = VK_SAMPLE_COUNT_1_BIT;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // the terrain frame blitted before
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  color.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  color.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
  VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &ref;
  // The caller's barrier made the image a colour attachment; order the
  // load after it.
  VkSubpassDependency dependency{};
  dependency.srcSubpass = VK_SUBPASS_EXTERNAL;
  dependency.dstSubpass = 0;
  dependency.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dependency.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dependency.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dependency.dstAccessMask =
      VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = 1;
  info.pAttachments = &color;
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = 1;
  info.pDependencies = &dependency;
  VkRenderPass pass = VK_NULL_HANDLE;
  AAL_VK_CHECK(vkCreateRenderPass(device, &info, nullptr, &pass));
  return pass;
}

VkDescriptorPool makeDescriptorPool(VkDevice device) {
  // The backend needs one combined image sampler (the font).
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4};
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  info.maxSets = 4;
  info.poolSizeCount = 1;
  info.pPoolSizes = &size;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  AAL_VK_CHECK(vkCreateDescriptorPool(device, &info, nullptr, &pool));
  return pool;
}

}  // namespace

UiOverlay::UiOverlay(const Instance& instance, const Device& device, const Window& window,
                     const Swapchain& swapchain)
    : device_(device) {
  renderPass_ = makeRenderPass(device.handle(), swapchain.format());
  descriptorPool_ = makeDescriptorPool(device.handle());

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini in the user's folder
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
  info.ImageCount = swapchain.imageCount();
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
    VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    info.renderPass = renderPass_;
    info.attachmentCount = 1;
    info.pAttachments = &view;
    info.width = extent_.width;
    info.height = extent_.height;
    info.layers = 1;
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
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  frameStarted_ = true;
}

void UiOverlay::record(VkCommandBuffer cmd, uint32_t imageIndex) {
  ImGui::Render();
  frameStarted_ = false;
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = renderPass_;
  begin.framebuffer = framebuffers_[imageIndex];
  begin.renderArea = {{0, 0}, extent_};
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
