// SPIR-V modules compiled at build time (cmake/Shaders.cmake) and built into
// the library (embedded_shaders.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "aperture/engine/vk/spirv_reflection.h"

namespace aal {

class Device;

// The SPIR-V of the shader built from `name`, e.g. "caps_parity.comp".
// Throws std::runtime_error naming it if no such shader is built in.
std::vector<uint32_t> loadSpirv(const std::string& name);

// A module and the descriptor bindings it declares (read from its SPIR-V).
class ShaderModule {
 public:
  // Throws std::runtime_error naming the shader if it cannot be read or
  // reflected.
  ShaderModule(const Device& device, const std::string& name);
  ~ShaderModule();
  ShaderModule(const ShaderModule&) = delete;
  ShaderModule& operator=(const ShaderModule&) = delete;

  VkShaderModule handle() const { return module_; }
  const std::string& name() const { return name_; }
  const ShaderInterface& shaderInterface() const { return interface_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  std::string name_;
  ShaderInterface interface_;
  VkShaderModule module_ = VK_NULL_HANDLE;
};

}  // namespace aal
