// Batched uploads through a staging buffer smaller than the data.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/image.h"
#include "aperture/engine/vk/upload.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

class Upload : public VulkanTest {};

TEST_F(Upload, ImagesAndBuffersArriveWholeThroughATinyStagingBuffer) {
  const uint32_t w = 37, h = 29;
  Image image(device(), {w, h, VK_FORMAT_R32_SFLOAT,
                         VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                             VK_IMAGE_USAGE_SAMPLED_BIT});
  std::vector<uint32_t> words(1000);
  std::iota(words.begin(), words.end(), 7u);
  Buffer buffer(device(), words.size() * 4,
                VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                MemoryIntent::DeviceLocal);

  // 512 bytes of staging: three rows of the image at a time, the buffer in
  // eight pieces, so many submissions.
  UploadBatch upload(device(), 512);
  int bands = 0;
  upload.addImage(image, sizeof(float), [&](uint32_t first, uint32_t end, void* destination) {
    auto* out = static_cast<float*>(destination);
    for (uint32_t row = first; row < end; ++row) {
      for (uint32_t col = 0; col < w; ++col) *out++ = float(row * 1000 + col);
    }
    ++bands;
  });
  upload.addBuffer(buffer, words.data(), words.size() * 4);
  upload.submit();
  EXPECT_GE(bands, 8);

  Buffer imageBack(device(), w * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::Readback);
  Buffer bufferBack(device(), words.size() * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                    MemoryIntent::Readback);
  submitAndWait(device(), [&](VkCommandBuffer cmd) {
    transitionImage(cmd, image, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {w, h, 1};
    vkCmdCopyImageToBuffer(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           imageBack.handle(), 1, &region);
    const VkBufferCopy copy{0, 0, words.size() * 4};
    vkCmdCopyBuffer(cmd, buffer.handle(), bufferBack.handle(), 1, &copy);
  });
  std::vector<float> pixels(w * h);
  imageBack.read(pixels.data(), pixels.size() * 4);
  for (uint32_t row = 0; row < h; ++row) {
    for (uint32_t col = 0; col < w; ++col) {
      ASSERT_EQ(pixels[row * w + col], float(row * 1000 + col)) << row << "," << col;
    }
  }
  std::vector<uint32_t> back(words.size());
  bufferBack.read(back.data(), back.size() * 4);
  EXPECT_EQ(back, words);
}

}  // namespace
}  // namespace aal
