// Vulkan instance with optional validation layer and a debug messenger that
// records every message, so tests can fail on any of them.
#pragma once

#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

struct InstanceOptions {
  // Enable VK_LAYER_KHRONOS_validation and the debug messenger. When unset,
  // the environment variable AAL_VALIDATION=1 turns it on.
  bool validation = false;
  // Extra instance extensions (e.g. those GLFW needs for a window surface).
  std::vector<const char*> extensions;
};

// Messages the validation layer reported (warnings and errors).
class ValidationLog {
 public:
  void add(std::string message);
  std::vector<std::string> messages() const;
  size_t count() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> messages_;
};

// "" without an address-space limit; else a sentence naming it (ulimit -v),
// for errors where the loader or a driver failed to map its libraries:
// such a limit, not a missing driver, is then the likely cause.
std::string addressSpaceLimitNote();

class Instance {
 public:
  explicit Instance(const InstanceOptions& options = {});
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  VkInstance handle() const { return instance_; }
  bool validationEnabled() const { return messenger_ != VK_NULL_HANDLE; }
  // Validation messages so far; empty when validation is off.
  const ValidationLog& validationLog() const { return log_; }

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  ValidationLog log_;
};

// True when AAL_VALIDATION=1 is set in the environment.
bool validationRequestedByEnvironment();

}  // namespace aal
