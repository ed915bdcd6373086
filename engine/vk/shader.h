// SPIR-V modules compiled at build time (cmake/Shaders.cmake).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

class Device;

// Folder holding the compiled shaders: $AAL_SHADER_DIR when set, else the
// build tree's shaders/ folder, else `<executable>/../shaders`.
std::filesystem::path shaderDirectory();

// Reads `<shaderDirectory()>/<name>.spv`, e.g. name "caps_parity.comp".
// Throws std::runtime_error naming the path if it is missing or malformed.
std::vector<uint32_t> loadSpirv(const std::string& name);

class ShaderModule {
 public:
  ShaderModule(const Device& device, const std::string& name);
  ~ShaderModule();
  ShaderModule(const ShaderModule&) = delete;
  ShaderModule& operator=(const ShaderModule&) = delete;

  VkShaderModule handle() const { return module_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkShaderModule module_ = VK_NULL_HANDLE;
};

}  // namespace aal
