#include "aperture/engine/vk/graphics_pipeline.h"

#include <stdexcept>

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/shader.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

namespace {

const ShaderInterface& checkStage(const ShaderModule& shader, VkShaderStageFlags stage) {
  if (shader.shaderInterface().stages != stage) {
    throw std::logic_error("shader " + shader.name() + " is not of the stage it is used for");
  }
  return shader.shaderInterface();
}

}  // namespace

GraphicsPipeline::GraphicsPipeline(const Device& device, const GraphicsPipelineDesc& desc)
    : GraphicsPipeline(device, desc, ShaderModule(device, desc.vertexShader),
                       ShaderModule(device, desc.fragmentShader)) {}

GraphicsPipeline::GraphicsPipeline(const Device& device, const GraphicsPipelineDesc& desc,
                                   const ShaderModule& vertex, const ShaderModule& fragment)
    : device_(device.handle()),
      layout_(device,
              mergeShaderInterfaces({checkStage(vertex, VK_SHADER_STAGE_VERTEX_BIT),
                                     checkStage(fragment, VK_SHADER_STAGE_FRAGMENT_BIT)}),
              desc.pushConstantBytes) {
  std::vector<VkSpecializationMapEntry> entries;
  for (uint32_t i = 0; i < desc.specialization.size(); ++i) {
    entries.push_back(
        {.constantID = i, .offset = i * uint32_t(sizeof(int32_t)), .size = sizeof(int32_t)});
  }
  const VkSpecializationInfo specialization{
      .mapEntryCount = static_cast<uint32_t>(entries.size()),
      .pMapEntries = entries.data(),
      .dataSize = desc.specialization.size() * sizeof(int32_t),
      .pData = desc.specialization.data()};
  const VkSpecializationInfo* constants = entries.empty() ? nullptr : &specialization;
  const VkPipelineShaderStageCreateInfo stages[2] = {
      {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
       .stage = VK_SHADER_STAGE_VERTEX_BIT,
       .module = vertex.handle(),
       .pName = "main",
       .pSpecializationInfo = constants},
      {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
       .stage = VK_SHADER_STAGE_FRAGMENT_BIT,
       .module = fragment.handle(),
       .pName = "main",
       .pSpecializationInfo = constants}};

  const VkPipelineVertexInputStateCreateInfo vertexInput{
      .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  const VkPipelineInputAssemblyStateCreateInfo assembly{
      .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
      .topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST};
  const VkPipelineViewportStateCreateInfo viewport{
      .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
      .viewportCount = 1,
      .scissorCount = 1};
  const VkPipelineRasterizationStateCreateInfo raster{
      .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
      .polygonMode = VK_POLYGON_MODE_FILL,
      .cullMode = desc.cullMode,
      .frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE,
      .lineWidth = 1.0f};
  const VkPipelineMultisampleStateCreateInfo multisample{
      .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
      .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT};
  const VkPipelineDepthStencilStateCreateInfo depth{
      .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
      .depthTestEnable = desc.depthTest,
      .depthWriteEnable = desc.depthWrite,
      .depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL};
  std::vector<VkPipelineColorBlendAttachmentState> blendAttachments(desc.colorFormats.size());
  for (size_t i = 0; i < blendAttachments.size(); ++i) {
    VkPipelineColorBlendAttachmentState& b = blendAttachments[i];
    if (desc.additiveBlend) {
      b = {.blendEnable = VK_TRUE,
           .srcColorBlendFactor = VK_BLEND_FACTOR_ONE,
           .dstColorBlendFactor = VK_BLEND_FACTOR_ONE,
           .colorBlendOp = VK_BLEND_OP_ADD,
           .srcAlphaBlendFactor = VK_BLEND_FACTOR_ZERO,
           .dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE,
           .alphaBlendOp = VK_BLEND_OP_ADD};
    }
    b.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                       VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    if ((desc.writtenColors >> i & 1u) == 0) b.colorWriteMask = 0;
  }
  const VkPipelineColorBlendStateCreateInfo blend{
      .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
      .attachmentCount = static_cast<uint32_t>(blendAttachments.size()),
      .pAttachments = blendAttachments.data()};
  const VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR,
                                          VK_DYNAMIC_STATE_CULL_MODE};
  const VkPipelineDynamicStateCreateInfo dynamic{
      .sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO,
      .dynamicStateCount = desc.dynamicCullMode ? 3u : 2u,
      .pDynamicStates = dynamicStates};
  const VkPipelineRenderingCreateInfo rendering{
      .sType = VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO,
      .colorAttachmentCount = static_cast<uint32_t>(desc.colorFormats.size()),
      .pColorAttachmentFormats = desc.colorFormats.data(),
      .depthAttachmentFormat = desc.depthFormat};

  const VkGraphicsPipelineCreateInfo info{.sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
                                          .pNext = &rendering,
                                          .stageCount = 2,
                                          .pStages = stages,
                                          .pVertexInputState = &vertexInput,
                                          .pInputAssemblyState = &assembly,
                                          .pViewportState = &viewport,
                                          .pRasterizationState = &raster,
                                          .pMultisampleState = &multisample,
                                          .pDepthStencilState = &depth,
                                          .pColorBlendState = &blend,
                                          .pDynamicState = &dynamic,
                                          .layout = layout_.handle()};
  AAL_VK_CHECK(vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_));
}

GraphicsPipeline::~GraphicsPipeline() {
  if (pipeline_ != VK_NULL_HANDLE) vkDestroyPipeline(device_, pipeline_, nullptr);
}

void GraphicsPipeline::bind(VkCommandBuffer cmd, const DescriptorWrites& writes,
                            const void* pushConstants) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_);
  writes.push(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_);
  if (pushConstants && layout_.pushConstantBytes() > 0) {
    vkCmdPushConstants(cmd, layout_.handle(), layout_.stages(), 0, layout_.pushConstantBytes(),
                       pushConstants);
  }
}

}  // namespace aal
