// Pipeline layouts with one push-descriptor set, and the writes that fill it.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "aperture/engine/vk/spirv_reflection.h"

namespace aal {

class Buffer;
class Device;

// The layout of a pipeline made of shader modules: set 0 holds the bindings
// their SPIR-V declares (`shaders`, mergeShaderInterfaces), bound with push
// descriptors; an optional push-constant block of pushConstantBytes is
// visible to all the pipeline's stages.
class PipelineLayout {
 public:
  // Throws std::logic_error if the shaders use a set other than 0 or a
  // runtime-sized array (lavapipe has no descriptor indexing).
  PipelineLayout(const Device& device, const ShaderInterface& shaders, uint32_t pushConstantBytes);
  ~PipelineLayout();
  PipelineLayout(const PipelineLayout&) = delete;
  PipelineLayout& operator=(const PipelineLayout&) = delete;

  VkPipelineLayout handle() const { return layout_; }
  VkShaderStageFlags stages() const { return stages_; }
  uint32_t pushConstantBytes() const { return pushConstantBytes_; }
  // Set 0's bindings, sorted.
  const std::vector<DescriptorBinding>& bindings() const { return bindings_; }
  // The type of set 0's `binding`; throws std::logic_error if there is none.
  VkDescriptorType descriptorType(uint32_t binding) const;
  PFN_vkCmdPushDescriptorSetKHR pushDescriptorSet() const { return pushDescriptorSet_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkShaderStageFlags stages_ = 0;
  uint32_t pushConstantBytes_ = 0;
  std::vector<DescriptorBinding> bindings_;
  PFN_vkCmdPushDescriptorSetKHR pushDescriptorSet_ = nullptr;
};

// Collects the resources of one draw or dispatch and pushes them. Each
// write's descriptor type is the one the pipeline's layout has at that
// binding (a buffer: uniform or storage; an image: sampled with `sampler`,
// or storage in VK_IMAGE_LAYOUT_GENERAL); push throws std::logic_error if a
// resource does not fit its binding.
class DescriptorWrites {
 public:
  DescriptorWrites& buffer(uint32_t binding, const Buffer& buffer);
  DescriptorWrites& image(uint32_t binding, VkImageView view, VkSampler sampler = VK_NULL_HANDLE);

  void push(VkCommandBuffer cmd, VkPipelineBindPoint bindPoint, const PipelineLayout& layout) const;

 private:
  struct Entry {
    uint32_t binding;
    bool isImage;
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
