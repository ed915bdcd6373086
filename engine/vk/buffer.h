// GPU buffers with memory chosen by intent rather than raw property flags.
#pragma once

#include <cstddef>

#include <vulkan/vulkan.h>

namespace aal {

class Device;

enum class MemoryIntent {
  DeviceLocal,  // GPU-only; filled by copies
  Upload,       // host-visible, written by the CPU, read by the GPU
  Readback,     // host-visible (cached where possible), written by the GPU
};

class Buffer {
 public:
  Buffer() = default;
  Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryIntent intent);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  // Host pointer for Upload/Readback buffers (persistently mapped), else null.
  void* mapped() const { return mapped_; }

  // Copies bytes in/out of a host-visible buffer, flushing/invalidating as needed.
  void write(const void* data, size_t bytes, size_t offset = 0);
  void read(void* data, size_t bytes, size_t offset = 0) const;
  // Makes host writes through mapped() visible to the device (a no-op on
  // coherent memory).
  void flush();

 private:
  void release();

  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
  bool coherent_ = false;
};

// Index of a memory type allowed by typeBits that has all `required` flags,
// preferring one that also has `preferred`. Throws VulkanError if none does.
uint32_t findMemoryType(const VkPhysicalDeviceMemoryProperties& memory, uint32_t typeBits,
                        VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred = 0);

}  // namespace aal
