// Compute pipelines whose descriptor set 0 is bound with push descriptors
// (a list of storage buffers, or any bindings), plus an optional
// push-constant block.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "descriptors.h"

namespace aal {

class Buffer;
class Device;

class ComputePipeline {
 public:
  // `shaderName` as for loadSpirv; bindings 0..storageBufferCount-1 of set 0
  // are storage buffers; pushConstantBytes may be 0.
  ComputePipeline(const Device& device, const std::string& shaderName, uint32_t storageBufferCount,
                  uint32_t pushConstantBytes);
  // Bindings 0..n-1 of set 0 of the given types.
  ComputePipeline(const Device& device, const std::string& shaderName,
                  const std::vector<VkDescriptorType>& bindings, uint32_t pushConstantBytes);
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  // Binds the pipeline and buffers, pushes constants and dispatches.
  void record(VkCommandBuffer cmd, const std::vector<const Buffer*>& buffers,
              const void* pushConstants, uint32_t groupsX, uint32_t groupsY = 1,
              uint32_t groupsZ = 1) const;
  // The same with any resources.
  void record(VkCommandBuffer cmd, const DescriptorWrites& writes, const void* pushConstants,
              uint32_t groupsX, uint32_t groupsY = 1, uint32_t groupsZ = 1) const;

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  PipelineLayout layout_;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace aal
