#include "aperture/engine/vk/compute.h"

#include <stdexcept>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/shader.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

ComputePipeline::ComputePipeline(const Device& device, const std::string& shaderName,
                                 uint32_t pushConstantBytes)
    : ComputePipeline(device, ShaderModule(device, shaderName), pushConstantBytes) {}

ComputePipeline::ComputePipeline(const Device& device, const ShaderModule& shader,
                                 uint32_t pushConstantBytes)
    : device_(device.handle()), layout_(device, shader.shaderInterface(), pushConstantBytes) {
  if (shader.shaderInterface().stages != VK_SHADER_STAGE_COMPUTE_BIT) {
    throw std::logic_error("shader " + shader.name() + " is not a compute shader");
  }
  const VkComputePipelineCreateInfo info{
      .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
      .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                .module = shader.handle(),
                .pName = "main"},
      .layout = layout_.handle()};
  AAL_VK_CHECK(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_));
}

ComputePipeline::~ComputePipeline() {
  if (pipeline_ != VK_NULL_HANDLE) vkDestroyPipeline(device_, pipeline_, nullptr);
}

void ComputePipeline::record(VkCommandBuffer cmd, const std::vector<const Buffer*>& buffers,
                             const void* pushConstants, uint32_t groupsX, uint32_t groupsY,
                             uint32_t groupsZ) const {
  if (buffers.size() != layout_.bindings().size()) {
    throw std::logic_error("ComputePipeline::record: wrong number of buffers");
  }
  DescriptorWrites writes;
  for (size_t i = 0; i < buffers.size(); ++i) {
    writes.buffer(static_cast<uint32_t>(i), *buffers[i]);
  }
  record(cmd, writes, pushConstants, groupsX, groupsY, groupsZ);
}

void ComputePipeline::record(VkCommandBuffer cmd, const DescriptorWrites& writes,
                             const void* pushConstants, uint32_t groupsX, uint32_t groupsY,
                             uint32_t groupsZ) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  writes.push(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_);
  if (layout_.pushConstantBytes() > 0) {
    vkCmdPushConstants(cmd, layout_.handle(), VK_SHADER_STAGE_COMPUTE_BIT, 0,
                       layout_.pushConstantBytes(), pushConstants);
  }
  vkCmdDispatch(cmd, groupsX, groupsY, groupsZ);
}

}  // namespace aal
