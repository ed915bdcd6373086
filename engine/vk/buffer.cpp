#include "aperture/engine/vk/buffer.h"

#include <cstring>
#include <stdexcept>
#include <utility>

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/vk_check.h"

namespace aal {

uint32_t findMemoryType(const VkPhysicalDeviceMemoryProperties& memory, uint32_t typeBits,
                        VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) {
  for (VkMemoryPropertyFlags wanted : {required | preferred, required}) {
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
      if ((typeBits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & wanted) == wanted) {
        return i;
      }
    }
  }
  throw VulkanError("no suitable Vulkan memory type");
}

Buffer::Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage,
               MemoryIntent intent)
    : device_(device.handle()), size_(size) {
  const VkBufferCreateInfo info{.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                                .size = size,
                                .usage = usage,
                                .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
  AAL_VK_CHECK(vkCreateBuffer(device_, &info, nullptr, &buffer_));

  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device_, buffer_, &requirements);

  VkMemoryPropertyFlags required = 0, preferred = 0;
  switch (intent) {
    case MemoryIntent::DeviceLocal: required = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT; break;
    case MemoryIntent::Upload:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
      preferred = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      break;
    case MemoryIntent::Readback:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
      preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
      break;
  }
  const uint32_t type =
      findMemoryType(device.memoryProperties(), requirements.memoryTypeBits, required, preferred);
  coherent_ = device.memoryProperties().memoryTypes[type].propertyFlags &
              VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;

  const VkMemoryAllocateInfo alloc{.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                   .allocationSize = requirements.size,
                                   .memoryTypeIndex = type};
  AAL_VK_CHECK(vkAllocateMemory(device_, &alloc, nullptr, &memory_));
  AAL_VK_CHECK(vkBindBufferMemory(device_, buffer_, memory_, 0));
  if (intent != MemoryIntent::DeviceLocal) {
    AAL_VK_CHECK(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
  }
}

Buffer::~Buffer() {
  release();
}

Buffer::Buffer(Buffer&& other) noexcept {
  *this = std::move(other);
}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    device_ = std::exchange(other.device_, VK_NULL_HANDLE);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    mapped_ = std::exchange(other.mapped_, nullptr);
    coherent_ = other.coherent_;
  }
  return *this;
}

void Buffer::release() {
  if (device_ == VK_NULL_HANDLE) return;
  if (buffer_ != VK_NULL_HANDLE) vkDestroyBuffer(device_, buffer_, nullptr);
  if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
}

void Buffer::write(const void* data, size_t bytes, size_t offset) {
  if (!mapped_ || offset + bytes > size_) throw std::logic_error("Buffer::write out of range");
  std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
  flush();
}

void Buffer::flush() {
  if (!mapped_ || coherent_) return;
  const VkMappedMemoryRange range{
      .sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, .memory = memory_, .size = VK_WHOLE_SIZE};
  AAL_VK_CHECK(vkFlushMappedMemoryRanges(device_, 1, &range));
}

void Buffer::read(void* data, size_t bytes, size_t offset) const {
  if (!mapped_ || offset + bytes > size_) throw std::logic_error("Buffer::read out of range");
  if (!coherent_) {
    const VkMappedMemoryRange range{
        .sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, .memory = memory_, .size = VK_WHOLE_SIZE};
    AAL_VK_CHECK(vkInvalidateMappedMemoryRanges(device_, 1, &range));
  }
  std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
}

}  // namespace aal
