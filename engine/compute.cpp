#include "compute.h"

#include <stdexcept>

#include "buffer.h"
#include "device.h"
#include "shader.h"
#include "vk_check.h"

namespace aal {

ComputePipeline::ComputePipeline(const Device& device, const std::string& shaderName,
                                 uint32_t storageBufferCount, uint32_t pushConstantBytes)
    : device_(device.handle()),
      storageBufferCount_(storageBufferCount),
      pushConstantBytes_(pushConstantBytes) {
  if (pushConstantBytes > device.properties().limits.maxPushConstantsSize) {
    throw VulkanError("push constants of " + shaderName + " exceed the device limit");
  }
  pushDescriptorSet_ = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
      vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));
  if (!pushDescriptorSet_) throw VulkanError("vkCmdPushDescriptorSetKHR unavailable");

  std::vector<VkDescriptorSetLayoutBinding> bindings(storageBufferCount);
  for (uint32_t i = 0; i < storageBufferCount; ++i) {
    bindings[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  }
  VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  setInfo.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  setInfo.bindingCount = storageBufferCount;
  setInfo.pBindings = bindings.data();
  AAL_VK_CHECK(vkCreateDescriptorSetLayout(device_, &setInfo, nullptr, &setLayout_));

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &setLayout_;
  layoutInfo.pushConstantRangeCount = pushConstantBytes > 0 ? 1 : 0;
  layoutInfo.pPushConstantRanges = &range;
  AAL_VK_CHECK(vkCreatePipelineLayout(device_, &layoutInfo, nullptr, &layout_));

  const ShaderModule module(device, shaderName);
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module.handle();
  info.stage.pName = "main";
  info.layout = layout_;
  AAL_VK_CHECK(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_));
}

ComputePipeline::~ComputePipeline() {
  if (pipeline_ != VK_NULL_HANDLE) vkDestroyPipeline(device_, pipeline_, nullptr);
  if (layout_ != VK_NULL_HANDLE) vkDestroyPipelineLayout(device_, layout_, nullptr);
  if (setLayout_ != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device_, setLayout_, nullptr);
}

void ComputePipeline::record(VkCommandBuffer cmd, const std::vector<const Buffer*>& buffers,
                             const void* pushConstants, uint32_t groupsX, uint32_t groupsY,
                             uint32_t groupsZ) const {
  if (buffers.size() != storageBufferCount_) {
    throw std::logic_error("ComputePipeline::record: wrong number of buffers");
  }
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (size_t i = 0; i < buffers.size(); ++i) {
    infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstBinding = static_cast<uint32_t>(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  pushDescriptorSet_(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0,
                     static_cast<uint32_t>(writes.size()), writes.data());
  if (pushConstantBytes_ > 0) {
    vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes_,
                       pushConstants);
  }
  vkCmdDispatch(cmd, groupsX, groupsY, groupsZ);
}

}  // namespace aal
