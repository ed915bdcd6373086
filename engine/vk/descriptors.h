// Pipeline layouts with one push-descriptor set, and the writes that fill it.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

class Buffer;
class Device;

// Set 0 holds bindings 0..n-1 of the given types, visible to `stages`; an
// optional push-constant block of pushConstantBytes follows.
class PipelineLayout {
 public:
  PipelineLayout(const Device& device, const std::vector<VkDescriptorType>& bindings,
                 VkShaderStageFlags stages, uint32_t pushConstantBytes);
  ~PipelineLayout();
  PipelineLayout(const PipelineLayout&) = delete;
  PipelineLayout& operator=(const PipelineLayout&) = delete;

  VkPipelineLayout handle() const { return layout_; }
  VkShaderStageFlags stages() const { return stages_; }
  uint32_t pushConstantBytes() const { return pushConstantBytes_; }
  size_t bindingCount() const { return bindingCount_; }
  PFN_vkCmdPushDescriptorSetKHR pushDescriptorSet() const { return pushDescriptorSet_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkShaderStageFlags stages_ = 0;
  uint32_t pushConstantBytes_ = 0;
  size_t bindingCount_ = 0;
  PFN_vkCmdPushDescriptorSetKHR pushDescriptorSet_ = nullptr;
};

// Collects the resources of one draw or dispatch and pushes them.
class DescriptorWrites {
 public:
  DescriptorWrites& uniformBuffer(uint32_t binding, const Buffer& buffer);
  DescriptorWrites& storageBuffer(uint32_t binding, const Buffer& buffer);
  DescriptorWrites& sampledImage(uint32_t binding, VkImageView view, VkSampler sampler);
  // An image a compute shader writes, in VK_IMAGE_LAYOUT_GENERAL.
  DescriptorWrites& storageImage(uint32_t binding, VkImageView view);

  void push(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint, const PipelineLayout& layout) const;

 private:
  struct Entry {
    uint32_t binding;
    VkDescriptorType type;
    VkDescriptorBufferInfo buffer;
    VkDescriptorImageInfo image;
  };
  std::vector<Entry> entries_;
};

// A linear (or nearest) sampler clamped to the edge.
class Sampler {
 public:
  // `mipmapped`: trilinear across an image's mip levels (else level 0 only);
  // `repeatU`: the first coordinate wraps around instead (a table over
  // azimuth).
  Sampler(const Device& device, VkFilter filter, bool mipmapped = false, bool repeatU = false);
  ~Sampler();
  Sampler(const Sampler&) = delete;
  Sampler& operator=(const Sampler&) = delete;
  VkSampler handle() const { return sampler_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkSampler sampler_ = VK_NULL_HANDLE;
};

}  // namespace aal
