// Vulkan error checking that stays on in release builds.
#pragma once

#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace aal {

// A Vulkan call failed, or no usable device exists. Tools map it to exit code 1.
class VulkanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Name of a VkResult, e.g. "VK_ERROR_OUT_OF_DEVICE_MEMORY".
const char* vkResultName(VkResult result);

[[noreturn]] void throwVkFailure(VkResult result, const char* call, const char* file, int line);

}  // namespace aal

// Checks a VkResult; on failure throws VulkanError naming the call, file and line.
#define AAL_VK_CHECK(call)                                            \
  do {                                                                \
    const VkResult aalVkResult_ = (call);                             \
    if (aalVkResult_ != VK_SUCCESS) {                                 \
      ::aal::throwVkFailure(aalVkResult_, #call, __FILE__, __LINE__); \
    }                                                                 \
  } while (0)
