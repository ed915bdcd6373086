#include "aperture/engine/vk/shader.h"

#include <algorithm>
#include <stdexcept>

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/embedded_shaders.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

namespace {

constexpr uint32_t kSpirvMagic = 0x07230203;

}  // namespace

std::vector<uint32_t> loadSpirv(const std::string& name) {
  const std::span<const EmbeddedShader> shaders = embeddedShaders();
  const auto found = std::find_if(shaders.begin(), shaders.end(),
                                  [&](const EmbeddedShader& s) { return name == s.name; });
  if (found == shaders.end()) {
    throw std::runtime_error("no shader named " + name + " is built into aperture");
  }
  if (found->wordCount < 5 || found->words[0] != kSpirvMagic) {
    throw std::runtime_error("shader " + name + " is not valid SPIR-V");
  }
  return {found->words, found->words + found->wordCount};
}

ShaderModule::ShaderModule(const Device& device, const std::string& name)
    : device_(device.handle()), name_(name) {
  const std::vector<uint32_t> code = loadSpirv(name);
  try {
    interface_ = reflectShaderInterface(code);
  } catch (const SpirvError& e) {
    throw SpirvError("shader " + name + ": " + e.what());
  }
  const VkShaderModuleCreateInfo info{.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
                                      .codeSize = code.size() * sizeof(uint32_t),
                                      .pCode = code.data()};
  AAL_VK_CHECK(vkCreateShaderModule(device_, &info, nullptr, &module_));
}

ShaderModule::~ShaderModule() {
  if (module_ != VK_NULL_HANDLE) vkDestroyShaderModule(device_, module_, nullptr);
}

}  // namespace aal
