// Batched uploads through a staging buffer of bounded size: the data of many
// images and buffers goes in as few submissions as the staging size allows
// (one for small scenes), never one wait per upload, and never a second full
// copy of a large texture in host memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

class Buffer;
class Device;
class Image;
struct UploadCopy;  // one copy out of a staging buffer (upload.cpp)

// Writes rows [firstRow, endRow) of an image, tightly packed, to `destination`.
using RowWriter = std::function<void(uint32_t firstRow, uint32_t endRow, void* destination)>;

// Makes one row of `width` texels of a mip level from two rows of the level
// above (2 * width texels each): each texel the mean of its 2 x 2 texels.
using MipReducer = void (*)(const unsigned char* upper, const unsigned char* lower,
                            unsigned char* out, uint32_t width);

class UploadBatch {
 public:
  static constexpr size_t kDefaultStagingBytes = size_t{64} << 20;

  explicit UploadBatch(const Device& device, size_t stagingBytes = kDefaultStagingBytes)
      : device_(device), stagingLimit_(stagingBytes) {}

  // The image is filled band by band by `rows` during submit(); it ends in
  // SHADER_READ_ONLY_OPTIMAL. bytesPerTexel matches the image's format.
  // Array images: add every layer, in order 0, 1, ..., one after the other.
  // Images with mip levels need `reduce` and sizes that are multiples of
  // 2^(levels - 1): each band of rows (a multiple of that many) brings its
  // rows of every level, made on the host from the band alone, so a level's
  // texels depend only on the level-0 texels they cover (not on the band, the
  // image size or the device).
  void addImage(const Image& image, size_t bytesPerTexel, RowWriter rows, uint32_t layer = 0,
                MipReducer reduce = nullptr);
  // Convenience: `data` (tightly packed rows) must stay alive until submit().
  void addImage(const Image& image, size_t bytesPerTexel, const void* data);
  // The buffer must have TRANSFER_DST usage; `data` lands at offset 0 and
  // must stay alive until submit().
  void addBuffer(const Buffer& buffer, const void* data, size_t bytes);

  // Copies everything, in as many staging-buffer loads as needed, and waits.
  void submit();
  // Records the copies into `cmd` instead, from one staging buffer of
  // everything (so mind the size), which it retires into the device's
  // DeletionQueue: nothing waits, and the data is on the device once `cmd`
  // has run. What was added must stay alive until this returns only.
  void record(VkCommandBuffer cmd);
  // Records only the next share into `cmd`: as many whole bands as fit one
  // staging buffer of `bytes` (at least one band, so every call makes
  // progress), retired into the device's DeletionQueue like record()'s.
  // Returns true once everything added has been recorded (the batch is then
  // empty). Between shares an image stays in TRANSFER_DST_OPTIMAL: nothing
  // may read it before the commands of its last share have run. What was
  // added must stay alive until the call that returns true.
  bool recordShare(VkCommandBuffer cmd, size_t bytes);
  // Staging bytes of what is still to be copied.
  size_t bytesLeft() const;

 private:
  struct Pending {
    const Image* image = nullptr;
    size_t bytesPerTexel = 0;
    RowWriter rows;
    uint32_t layer = 0;
    MipReducer reduce = nullptr;
    const Buffer* buffer = nullptr;
    const unsigned char* data = nullptr;
    size_t bytes = 0;
    size_t done = 0;  // rows (images) or bytes (buffers) already copied
  };

  // submit() with staging loads of at most `limit` bytes; with `cmd`, record().
  void transfer(size_t limit, VkCommandBuffer cmd);
  // The staging size of a load of at most `limit` bytes: at least the
  // widest band of any image, so that a load always makes progress.
  size_t loadCapacity(size_t limit) const;
  // Fills `mapped` (capacity bytes) with what comes next, from pending_[next_]
  // on, and returns the copies that take it to the device.
  std::vector<UploadCopy> fill(unsigned char* mapped, size_t capacity);

  const Device& device_;
  size_t stagingLimit_;
  std::vector<Pending> pending_;
  size_t next_ = 0;  // pending_[next_] is the first not wholly copied
};

}  // namespace aal
