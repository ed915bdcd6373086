// Graphics pipelines for dynamic rendering, with no vertex input: vertex
// shaders pull their data (gl_VertexIndex, textures, storage buffers).
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "aperture/engine/vk/descriptors.h"

namespace aal {

class Device;
class ShaderModule;

struct GraphicsPipelineDesc {
  std::string vertexShader;    // e.g. "terrain.vert" (see loadSpirv)
  std::string fragmentShader;  // e.g. "terrain.frag"
  // (Descriptor bindings: those the two shaders declare, read from their SPIR-V.)
  uint32_t pushConstantBytes = 0;
  std::vector<VkFormat> colorFormats;
  VkFormat depthFormat = VK_FORMAT_UNDEFINED;
  bool depthTest = false;
  bool depthWrite = false;
  VkCullModeFlags cullMode = VK_CULL_MODE_NONE;
  // The cull mode is set per draw (vkCmdSetCullMode) instead of `cullMode`.
  bool dynamicCullMode = false;
  // Colour added to the target (ONE + ONE), alpha kept; else replaced.
  bool additiveBlend = false;
  // Specialisation constants of both stages: constant_id i takes
  // specialization[i] (32-bit ints and bools).
  std::vector<int32_t> specialization;
  // Bit i set: colour attachment i is written (else its write mask is 0 and
  // it keeps what it holds).
  uint32_t writtenColors = ~0u;
};

class GraphicsPipeline {
 public:
  GraphicsPipeline(const Device& device, const GraphicsPipelineDesc& desc);
  ~GraphicsPipeline();
  GraphicsPipeline(const GraphicsPipeline&) = delete;
  GraphicsPipeline& operator=(const GraphicsPipeline&) = delete;

  VkPipeline handle() const { return pipeline_; }
  const PipelineLayout& layout() const { return layout_; }

  // Binds the pipeline, pushes descriptors and constants (may be null).
  void bind(VkCommandBuffer cmd, const DescriptorWrites& writes, const void* pushConstants) const;

 private:
  GraphicsPipeline(const Device& device, const GraphicsPipelineDesc& desc,
                   const ShaderModule& vertex, const ShaderModule& fragment);

  VkDevice device_ = VK_NULL_HANDLE;
  PipelineLayout layout_;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace aal
