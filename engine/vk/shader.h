// SPIR-V modules compiled at build time (cmake/Shaders.cmake).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "spirv_reflection.h"

namespace aal {

class Device;

// Folder holding the compiled shaders: $AAL_SHADER_DIR when set, else the
// build tree's shaders/ folder, else `<executable>/../shaders`.
std::filesystem::path shaderDirectory();

// Reads `<shaderDirectory()>/<name>.spv`, e.g. name "caps_parity.comp".
// Throws std::runtime_error naming the path if it is missing or malformed.
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
