// Physical device selection and the logical device with one graphics+compute queue.
// Any Vulkan 1.3 device is accepted, CPU implementations (lavapipe) included.
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "aperture/engine/vk/deletion_queue.h"

namespace aal {

class Instance;

struct PhysicalDeviceInfo {
  VkPhysicalDevice handle = VK_NULL_HANDLE;
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t apiVersion = 0;
  bool usable = false;      // Vulkan 1.3, a graphics+compute queue, push descriptors
  std::string whyUnusable;  // empty when usable
};

// Every physical device the instance sees, in enumeration order (the order
// that --device N refers to).
std::vector<PhysicalDeviceInfo> listPhysicalDevices(const Instance& instance);

class Device {
 public:
  // deviceIndex < 0 picks the best usable device (discrete > integrated >
  // virtual > CPU). Throws VulkanError with a helpful message when none fits,
  // InputError when deviceIndex names no usable device (the user chose it).
  Device(const Instance& instance, int deviceIndex = -1,
         const std::vector<const char*>& extraExtensions = {});
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  VkDevice handle() const { return device_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  // The independentBlend feature is on (per-attachment blend and write masks).
  bool independentBlend() const { return independentBlend_; }
  const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memory_; }
  std::string name() const { return properties_.deviceName; }

  // Blocks until the device is idle (used at shutdown and in tests).
  void waitIdle() const;
  // What is retired while frames may still use it, destroyed when they have
  // completed (engine/vk/deletion_queue.h); the rest at the device's end.
  // Reached through a const Device, as every resource holds its device:
  // retiring changes no state of the device.
  DeletionQueue& deletionQueue() const { return deletions_; }

 private:
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;
  VkPhysicalDeviceProperties properties_{};
  bool independentBlend_ = false;
  VkPhysicalDeviceMemoryProperties memory_{};
  mutable DeletionQueue deletions_;
};

}  // namespace aal
