#include "aperture/engine/vk/descriptors.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

PipelineLayout::PipelineLayout(const Device& device, const ShaderInterface& shaders,
                               uint32_t pushConstantBytes)
    : device_(device.handle()),
      stages_(shaders.stages),
      pushConstantBytes_(pushConstantBytes),
      bindings_(shaders.bindings) {
  if (pushConstantBytes > device.properties().limits.maxPushConstantsSize) {
    throw VulkanError("push constants exceed the device limit");
  }
  pushDescriptorSet_ = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
      vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));
  if (!pushDescriptorSet_) throw VulkanError("vkCmdPushDescriptorSetKHR unavailable");
  std::vector<VkDescriptorSetLayoutBinding> list;
  for (const DescriptorBinding& b : bindings_) {
    // One push-descriptor set, no descriptor indexing (docs/design.md §11).
    if (b.set != 0) {
      throw std::logic_error("binding " + std::to_string(b.binding) + " is in set " +
                             std::to_string(b.set) + "; pipelines have set 0 only");
    }
    if (b.count == 0) {
      throw std::logic_error("binding " + std::to_string(b.binding) +
                             " is a runtime-sized array, which needs descriptor indexing");
    }
    list.push_back({.binding = b.binding,
                    .descriptorType = b.type,
                    .descriptorCount = b.count,
                    .stageFlags = b.stages});
  }
  const VkDescriptorSetLayoutCreateInfo setInfo{
      .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
      .flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR,
      .bindingCount = static_cast<uint32_t>(list.size()),
      .pBindings = list.data()};
  AAL_VK_CHECK(vkCreateDescriptorSetLayout(device_, &setInfo, nullptr, &setLayout_));

  const VkPushConstantRange range{.stageFlags = stages_, .offset = 0, .size = pushConstantBytes};
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

VkDescriptorType PipelineLayout::descriptorType(uint32_t binding) const {
  // (Set 0 only, sorted by binding: the constructor checked.)
  const auto at = std::lower_bound(
      bindings_.begin(), bindings_.end(), binding,
      [](const DescriptorBinding& b, uint32_t wanted) { return b.binding < wanted; });
  if (at == bindings_.end() || at->binding != binding) {
    throw std::logic_error("the pipeline's shaders declare no binding " + std::to_string(binding));
  }
  return at->type;
}

DescriptorWrites& DescriptorWrites::buffer(uint32_t binding, const Buffer& buffer) {
  entries_.push_back({.binding = binding,
                      .isImage = false,
                      .buffer = {.buffer = buffer.handle(), .offset = 0, .range = VK_WHOLE_SIZE},
                      .image = {}});
  return *this;
}

DescriptorWrites& DescriptorWrites::image(uint32_t binding, VkImageView view, VkSampler sampler) {
  entries_.push_back(
      {.binding = binding,
       .isImage = true,
       .buffer = {},
       .image = {.sampler = sampler, .imageView = view, .imageLayout = VK_IMAGE_LAYOUT_UNDEFINED}});
  return *this;
}

void DescriptorWrites::push(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint,
                            const PipelineLayout& layout) const {
  std::vector<VkDescriptorImageInfo> images(entries_.size());
  std::vector<VkWriteDescriptorSet> writes(entries_.size());
  for (size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    const VkDescriptorType type = layout.descriptorType(e.binding);
    const bool bufferType =
        type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER || type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    const bool imageType = type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER ||
                           type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    if (e.isImage ? !imageType : !bufferType) {
      throw std::logic_error("binding " + std::to_string(e.binding) + " is given " +
                             (e.isImage ? "an image" : "a buffer") +
                             ", which its descriptor type cannot hold");
    }
    images[i] = e.image;
    if (type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE) {
      images[i].imageLayout = VK_IMAGE_LAYOUT_GENERAL;
    } else if (type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER) {
      if (e.image.sampler == VK_NULL_HANDLE) {
        throw std::logic_error("binding " + std::to_string(e.binding) + " samples: give a sampler");
      }
      images[i].imageLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    }
    writes[i] = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                 .dstBinding = e.binding,
                 .descriptorCount = 1,
                 .descriptorType = type,
                 .pImageInfo = e.isImage ? &images[i] : nullptr,
                 .pBufferInfo = e.isImage ? nullptr : &e.buffer};
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
