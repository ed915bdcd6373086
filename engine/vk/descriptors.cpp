#include "descriptors.h"

#include <stdexcept>

#include "buffer.h"
#include "device.h"
#include "vk_check.h"

namespace aal {

PipelineLayout::PipelineLayout(const Device& device, const std::vector<VkDescriptorType>& bindings,
                               VkShaderStageFlags stages, uint32_t pushConstantBytes)
    : device_(device.handle()),
      stages_(stages),
      pushConstantBytes_(pushConstantBytes),
      bindingCount_(bindings.size()) {
  if (pushConstantBytes > device.properties().limits.maxPushConstantsSize) {
    throw VulkanError("push constants exceed the device limit");
  }
  pushDescriptorSet_ = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
      vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));
  if (!pushDescriptorSet_) throw VulkanError("vkCmdPushDescriptorSetKHR unavailable");
  std::vector<VkDescriptorSetLayoutBinding> list(bindings.size());
  for (uint32_t i = 0; i < bindings.size(); ++i) {
    list[i] = {
        .binding = i, .descriptorType = bindings[i], .descriptorCount = 1, .stageFlags = stages};
  }
  const VkDescriptorSetLayoutCreateInfo setInfo{
      .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
      .flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR,
      .bindingCount = static_cast<uint32_t>(list.size()),
      .pBindings = list.data()};
  AAL_VK_CHECK(vkCreateDescriptorSetLayout(device_, &setInfo, nullptr, &setLayout_));

  const VkPushConstantRange range{.stageFlags = stages, .offset = 0, .size = pushConstantBytes};
  const VkPipelineLayoutCreateInfo info{.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
                                        .setLayoutCount = 1,
                                        .pSetLayouts = &setLayout_,
                                        .pushConstantRangeCount = pushConstantBytes > 0 ? 1u : 0u,
                                        .pPushConstantRanges = &range};
  AAL_VK_CHECK(vkCreatePipelineLayout(device_, &info, nullptr, &layout_));
}

PipelineLayout::~PipelineLayout() {
  if (layout_ != VK_NULL_HANDLE) vkDestroyPipelineLayout(device_, layout_, nullptr);
  if (setLayout_ != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device_, setLayout_, nullptr);
}

DescriptorWrites& DescriptorWrites::uniformBuffer(uint32_t binding, const Buffer& buffer) {
  entries_.push_back({.binding = binding,
                      .type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                      .buffer = {.buffer = buffer.handle(), .offset = 0, .range = VK_WHOLE_SIZE}});
  return *this;
}

DescriptorWrites& DescriptorWrites::storageBuffer(uint32_t binding, const Buffer& buffer) {
  entries_.push_back({.binding = binding,
                      .type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                      .buffer = {.buffer = buffer.handle(), .offset = 0, .range = VK_WHOLE_SIZE}});
  return *this;
}

DescriptorWrites& DescriptorWrites::sampledImage(uint32_t binding, VkImageView view,
                                                 VkSampler sampler) {
  entries_.push_back({.binding = binding,
                      .type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                      .image = {.sampler = sampler,
                                .imageView = view,
                                .imageLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}});
  return *this;
}

DescriptorWrites& DescriptorWrites::storageImage(uint32_t binding, VkImageView view) {
  entries_.push_back(
      {.binding = binding,
       .type = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
       .image = {
           .sampler = VK_NULL_HANDLE, .imageView = view, .imageLayout = VK_IMAGE_LAYOUT_GENERAL}});
  return *this;
}

void DescriptorWrites::push(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint,
                            const PipelineLayout& layout) const {
  std::vector<VkWriteDescriptorSet> writes(entries_.size());
  for (size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    const bool image = e.type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER ||
                       e.type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    writes[i] = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                 .dstBinding = e.binding,
                 .descriptorCount = 1,
                 .descriptorType = e.type,
                 .pImageInfo = image ? &e.image : nullptr,
                 .pBufferInfo = image ? nullptr : &e.buffer};
  }
  layout.pushDescriptorSet()(cmd, bindPoint, layout.handle(), 0,
                             static_cast<uint32_t>(writes.size()), writes.data());
}

Sampler::Sampler(const Device& device, VkFilter filter, bool mipmapped, bool repeatU)
    : device_(device.handle()) {
  const VkSamplerCreateInfo info{
      .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
      .magFilter = filter,
      .minFilter = filter,
      .mipmapMode = mipmapped ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST,
      .addressModeU =
          repeatU ? VK_SAMPLER_ADDRESS_MODE_REPEAT : VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
      .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
      .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
      .maxLod = mipmapped ? VK_LOD_CLAMP_NONE : 0.0f};
  AAL_VK_CHECK(vkCreateSampler(device_, &info, nullptr, &sampler_));
}

Sampler::~Sampler() {
  if (sampler_ != VK_NULL_HANDLE) vkDestroySampler(device_, sampler_, nullptr);
}

}  // namespace aal
