// Compute pipelines whose descriptor set 0 (the bindings the shader
// declares, read from its SPIR-V) is bound with push descriptors, plus an
// optional push-constant block.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "aperture/engine/vk/descriptors.h"

namespace aal {

class Buffer;
class Device;
class ShaderModule;

class ComputePipeline {
 public:
  // `shaderName` as for loadSpirv; pushConstantBytes may be 0.
  ComputePipeline(const Device& device, const std::string& shaderName, uint32_t pushConstantBytes);
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  // Binds the pipeline and buffers (buffers[i] at binding i; the shader
  // declares bindings 0..n-1, all buffers), pushes constants and dispatches.
  void record(VkCommandBuffer cmd, const std::vector<const Buffer*>& buffers,
              const void* pushConstants, uint32_t groupsX, uint32_t groupsY = 1,
              uint32_t groupsZ = 1) const;
  // The same with any resources.
  void record(VkCommandBuffer cmd, const DescriptorWrites& writes, const void* pushConstants,
              uint32_t groupsX, uint32_t groupsY = 1, uint32_t groupsZ = 1) const;

 private:
  ComputePipeline(const Device& device, const ShaderModule& shader, uint32_t pushConstantBytes);

  VkDevice device_ = VK_NULL_HANDLE;
  PipelineLayout layout_;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace aal
