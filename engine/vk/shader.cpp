#include "shader.h"

#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "device.h"
#include "vk_check.h"

#ifndef AAL_BUILD_SHADER_DIR
#define AAL_BUILD_SHADER_DIR ""
#endif

namespace aal {

namespace {

constexpr uint32_t kSpirvMagic = 0x07230203;

std::filesystem::path executableDirectory() {
  std::error_code error;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::filesystem::path() : exe.parent_path();
}

}  // namespace

std::filesystem::path shaderDirectory() {
  if (const char* env = std::getenv("AAL_SHADER_DIR"); env && *env) return env;
  const std::filesystem::path built = AAL_BUILD_SHADER_DIR;
  if (!built.empty() && std::filesystem::is_directory(built)) return built;
  return executableDirectory() / ".." / "shaders";
}

std::vector<uint32_t> loadSpirv(const std::string& name) {
  const std::filesystem::path path = shaderDirectory() / (name + ".spv");
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) throw std::runtime_error("cannot open shader " + path.string());
  const std::streamsize bytes = file.tellg();
  if (bytes <= 0 || bytes % 4 != 0) {
    throw std::runtime_error("shader " + path.string() + " is not valid SPIR-V (size)");
  }
  std::vector<uint32_t> words(static_cast<size_t>(bytes) / 4);
  file.seekg(0);
  file.read(reinterpret_cast<char*>(words.data()), bytes);
  if (!file || words[0] != kSpirvMagic) {
    throw std::runtime_error("shader " + path.string() + " is not valid SPIR-V");
  }
  return words;
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
