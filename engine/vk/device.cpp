#include "aperture/engine/vk/device.h"

#include <cstring>

#include "aperture/engine/vk/instance.h"
#include "aperture/engine/vk/vk_check.h"
#include "aperture/terrain/errors.h"

namespace aal {

namespace {

constexpr uint32_t kQueueFlags = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;

int findQueueFamily(VkPhysicalDevice physical) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, families.data());
  for (uint32_t i = 0; i < count; ++i) {
    if ((families[i].queueFlags & kQueueFlags) == kQueueFlags) return static_cast<int>(i);
  }
  return -1;
}

bool hasExtension(VkPhysicalDevice physical, const char* name) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, extensions.data());
  for (const VkExtensionProperties& e : extensions) {
    if (std::strcmp(e.extensionName, name) == 0) return true;
  }
  return false;
}

int typeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
  }
}

std::string describeDevices(const std::vector<PhysicalDeviceInfo>& devices) {
  std::string text;
  for (size_t i = 0; i < devices.size(); ++i) {
    text += "\n  [" + std::to_string(i) + "] " + devices[i].name +
            (devices[i].usable ? "" : " (unusable: " + devices[i].whyUnusable + ")");
  }
  return text;
}

}  // namespace

std::vector<PhysicalDeviceInfo> listPhysicalDevices(const Instance& instance) {
  uint32_t count = 0;
  const VkResult listed = vkEnumeratePhysicalDevices(instance.handle(), &count, nullptr);
  // lavapipe fails to start its threads and memory under a tight ulimit -v.
  if (listed == VK_ERROR_INITIALIZATION_FAILED || listed == VK_ERROR_OUT_OF_HOST_MEMORY) {
    const std::string limit = addressSpaceLimitNote();
    if (!limit.empty()) {
      throw VulkanError("the Vulkan driver could not start (" + std::string(vkResultName(listed)) +
                        "): " + limit);
    }
  }
  AAL_VK_CHECK(listed);
  std::vector<VkPhysicalDevice> handles(count);
  AAL_VK_CHECK(vkEnumeratePhysicalDevices(instance.handle(), &count, handles.data()));

  std::vector<PhysicalDeviceInfo> devices;
  for (VkPhysicalDevice handle : handles) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(handle, &props);
    PhysicalDeviceInfo info;
    info.handle = handle;
    info.name = props.deviceName;
    info.type = props.deviceType;
    info.apiVersion = props.apiVersion;
    if (props.apiVersion < VK_API_VERSION_1_3) {
      info.whyUnusable = "Vulkan 1.3 required";
    } else if (findQueueFamily(handle) < 0) {
      info.whyUnusable = "no graphics+compute queue";
    } else if (!hasExtension(handle, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) {
      info.whyUnusable = "VK_KHR_push_descriptor missing";
    }
    info.usable = info.whyUnusable.empty();
    devices.push_back(info);
  }
  return devices;
}

Device::Device(const Instance& instance, int deviceIndex,
               const std::vector<const char*>& extraExtensions) {
  const std::vector<PhysicalDeviceInfo> devices = listPhysicalDevices(instance);
  if (devices.empty()) {
    throw VulkanError(
        "no Vulkan device found; install a driver (sudo apt-get install mesa-vulkan-drivers "
        "gives lavapipe, a CPU implementation)");
  }
  int chosen = -1;
  if (deviceIndex >= 0) {
    if (deviceIndex >= static_cast<int>(devices.size()) || !devices[deviceIndex].usable) {
      // The user's choice (--device), not the system, is at fault: exit 2.
      throw InputError("--device " + std::to_string(deviceIndex) +
                       " is not available; devices:" + describeDevices(devices));
    }
    chosen = deviceIndex;
  } else {
    for (size_t i = 0; i < devices.size(); ++i) {
      if (devices[i].usable &&
          (chosen < 0 || typeRank(devices[i].type) > typeRank(devices[chosen].type))) {
        chosen = static_cast<int>(i);
      }
    }
    if (chosen < 0) {
      throw VulkanError("no usable Vulkan device; devices:" + describeDevices(devices));
    }
  }

  physical_ = devices[chosen].handle;
  queueFamily_ = static_cast<uint32_t>(findQueueFamily(physical_));
  vkGetPhysicalDeviceProperties(physical_, &properties_);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

  const float priority = 1.0f;
  const VkDeviceQueueCreateInfo queueInfo{.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                          .queueFamilyIndex = queueFamily_,
                                          .queueCount = 1,
                                          .pQueuePriorities = &priority};

  std::vector<const char*> extensions = extraExtensions;
  extensions.push_back(VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);

  VkPhysicalDeviceVulkan13Features features13{
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES,
      .synchronization2 = VK_TRUE,
      .dynamicRendering = VK_TRUE};
  // Where there is one: the renderer draws the sky in the terrain's
  // rendering with the G-buffer's other targets masked off.
  VkPhysicalDeviceFeatures supported{};
  vkGetPhysicalDeviceFeatures(physical_, &supported);
  independentBlend_ = supported.independentBlend == VK_TRUE;
  VkPhysicalDeviceFeatures2 features{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
                                     .pNext = &features13,
                                     .features = {.independentBlend = supported.independentBlend}};

  const VkDeviceCreateInfo info{.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
                                .pNext = &features,
                                .queueCreateInfoCount = 1,
                                .pQueueCreateInfos = &queueInfo,
                                .enabledExtensionCount = static_cast<uint32_t>(extensions.size()),
                                .ppEnabledExtensionNames = extensions.data()};
  AAL_VK_CHECK(vkCreateDevice(physical_, &info, nullptr, &device_));
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
}

Device::~Device() {
  if (device_ != VK_NULL_HANDLE) {
    vkDeviceWaitIdle(device_);
    // Idle: whatever is still retired goes before the device.
    deletions_.releaseAll();
    vkDestroyDevice(device_, nullptr);
  }
}

void Device::waitIdle() const {
  AAL_VK_CHECK(vkDeviceWaitIdle(device_));
}

}  // namespace aal
