#include "aperture/engine/vk/instance.h"

#include <sys/resource.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

#include "aperture/engine/vk/vk_check.h"
#include "aperture/terrain/io/memory_budget.h"

namespace aal {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSynchronizationValidation = false;
#else
constexpr bool kSynchronizationValidation = true;
#endif

bool layerAvailable(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const VkLayerProperties& layer : layers) {
    if (std::strcmp(layer.layerName, name) == 0) return true;
  }
  return false;
}

VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data,
                                              void* userData) {
  const char* level =
      (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error" : "warning";
  std::string message = std::string("vulkan validation ") + level + ": " + data->pMessage;
  std::cerr << message << "\n";
  static_cast<ValidationLog*>(userData)->add(std::move(message));
  return VK_FALSE;  // never abort the call; the test decides
}

VkDebugUtilsMessengerCreateInfoEXT messengerInfo(ValidationLog* log) {
  return {.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
          .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                             VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
          .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
          .pfnUserCallback = onDebugMessage,
          .pUserData = log};
}

}  // namespace

void ValidationLog::add(std::string message) {
  std::lock_guard lock(mutex_);
  messages_.push_back(std::move(message));
}

std::vector<std::string> ValidationLog::messages() const {
  std::lock_guard lock(mutex_);
  return messages_;
}

size_t ValidationLog::count() const {
  std::lock_guard lock(mutex_);
  return messages_.size();
}

bool validationRequestedByEnvironment() {
  const char* value = std::getenv("AAL_VALIDATION");
  return value && std::strcmp(value, "1") == 0;
}

std::string addressSpaceLimitNote() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return "";
  return "this process's address space is limited (ulimit -v " +
         std::to_string(limit.rlim_cur >> 10) +
         " kB), which keeps the Vulkan driver from loading: raise or remove the limit";
}

namespace {

// Address space a driver needs to start: lavapipe's LLVM JIT and its
// threads abort the process ("LLVM ERROR: Unable to allocate section
// memory") or crash below it. Measured with aal-render, a 64x64 frame:
// 507 MiB left crashed or aborted; 800 MiB left (ulimit -v 1300000) started.
constexpr uint64_t kDriverAddressSpaceBytes = uint64_t{768} << 20;

// Refuses before the driver loads when the address-space limit leaves it
// too little: a clear error instead of an abort inside the driver.
void requireDriverAddressSpace() {
  if (const std::optional<std::string> shortfall =
          addressSpaceShortfall(kDriverAddressSpaceBytes, "the driver")) {
    throw VulkanError("cannot start Vulkan: " + *shortfall);
  }
}

}  // namespace

Instance::Instance(const InstanceOptions& options) {
  requireDriverAddressSpace();
  const bool validation = options.validation || validationRequestedByEnvironment();
  if (validation && !layerAvailable(kValidationLayer)) {
    throw VulkanError(std::string("validation requested but ") + kValidationLayer +
                      " is not installed (sudo apt-get install vulkan-validationlayers)");
  }

  std::vector<const char*> extensions = options.extensions;
  std::vector<const char*> layers;
  if (validation) {
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    layers.push_back(kValidationLayer);
  }

  const VkApplicationInfo app{.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                              .pApplicationName = "aperture",
                              .pEngineName = "aperture",
                              .apiVersion = VK_API_VERSION_1_3};

  // Chained so that instance creation and destruction are validated too.
  const VkDebugUtilsMessengerCreateInfoEXT debugInfo = messengerInfo(&log_);
  // Synchronisation validation besides the layer's default checks: a
  // missing or too narrow barrier between two commands of a submission that
  // touch the same memory is a message too (docs/viewer.md, "Frames in
  // flight", for what it does not see). Not under AddressSanitizer: these
  // checks leave allocations behind, and the loader unloads the layer with
  // the instance, so that LeakSanitizer can no longer name the layer to
  // suppress them (scripts/lsan.supp); the plain build's tests check it.
  const VkValidationFeatureEnableEXT enabled[] = {
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  const VkValidationFeaturesEXT features{
      .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
      .pNext = &debugInfo,
      .enabledValidationFeatureCount = kSynchronizationValidation ? 1u : 0u,
      .pEnabledValidationFeatures = enabled};
  const VkInstanceCreateInfo info{.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                                  .pNext = validation ? &features : nullptr,
                                  .pApplicationInfo = &app,
                                  .enabledLayerCount = static_cast<uint32_t>(layers.size()),
                                  .ppEnabledLayerNames = layers.data(),
                                  .enabledExtensionCount = static_cast<uint32_t>(extensions.size()),
                                  .ppEnabledExtensionNames = extensions.data()};

  const VkResult result = vkCreateInstance(&info, nullptr, &instance_);
  if (result == VK_ERROR_OUT_OF_HOST_MEMORY) {
    throw VulkanError(
        "cannot start Vulkan: out of memory (VK_ERROR_OUT_OF_HOST_MEMORY); free "
        "memory or raise the process's limit (ulimit -v)");
  }
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER) {
    // Under an address-space limit the loader cannot map an installed
    // driver and reports none: say so rather than ask for one.
    const std::string limit = addressSpaceLimitNote();
    if (!limit.empty()) throw VulkanError("no Vulkan 1.3 driver could be loaded: " + limit);
    throw VulkanError(
        "no Vulkan 1.3 driver found; install one (sudo apt-get install mesa-vulkan-drivers "
        "gives lavapipe, a CPU implementation)");
  }
  AAL_VK_CHECK(result);

  if (validation) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    AAL_VK_CHECK(create(instance_, &debugInfo, nullptr, &messenger_));
  }
}

Instance::~Instance() {
  if (messenger_ != VK_NULL_HANDLE) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance_, messenger_, nullptr);
  }
  if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

}  // namespace aal
