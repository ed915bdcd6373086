// Batched uploads: data for many images and buffers goes into one staging
// buffer and one command buffer, submitted once (no wait per upload).
#pragma once

#include <cstddef>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

class Buffer;
class Device;
class Image;

class UploadBatch {
 public:
  explicit UploadBatch(const Device& device) : device_(device) {}

  // `data` must stay alive until submit() (it is copied straight into the
  // staging memory then, so nothing is held twice). The image ends in
  // SHADER_READ_ONLY_OPTIMAL; `bytes` is its full size, rows tightly packed.
  void addImage(const Image& image, const void* data, size_t bytes);
  // The buffer must have TRANSFER_DST usage; the data lands at offset 0.
  void addBuffer(const Buffer& buffer, const void* data, size_t bytes);

  // Fills one staging buffer, records every copy in one command buffer,
  // submits it and waits.
  void submit();

 private:
  struct Pending {
    const Image* image = nullptr;
    const Buffer* buffer = nullptr;
    const void* data = nullptr;
    size_t offset = 0, bytes = 0;
  };
  void add(const Image* image, const Buffer* buffer, const void* data, size_t bytes);

  const Device& device_;
  size_t stagingBytes_ = 0;
  std::vector<Pending> pending_;
};

}  // namespace aal
