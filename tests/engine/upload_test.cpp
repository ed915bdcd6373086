// Batched uploads through a staging buffer smaller than the data.
#include <gtest/gtest.h>

#include <memory>
#include <numeric>
#include <vector>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/image.h"
#include "aperture/engine/vk/upload.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

class Upload : public VulkanTest {
 protected:
  static constexpr uint32_t w = 37, h = 29;

  void SetUp() override {
    VulkanTest::SetUp();
    image_ = std::make_unique<Image>(
        device(), ImageDesc{w, h, VK_FORMAT_R32_SFLOAT,
                            VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                VK_IMAGE_USAGE_SAMPLED_BIT});
    std::iota(words_.begin(), words_.end(), 7u);
    buffer_ = std::make_unique<Buffer>(
        device(), words_.size() * 4,
        VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
        MemoryIntent::DeviceLocal);
  }

  void TearDown() override {
    image_.reset();
    buffer_.reset();
    VulkanTest::TearDown();
  }

  // The image (texel row * 1000 + col, written a band at a time) and the
  // buffer added to `upload`.
  void add(UploadBatch& upload) {
    upload.addImage(*image_, sizeof(float),
                    [this](uint32_t first, uint32_t end, void* destination) {
                      auto* out = static_cast<float*>(destination);
                      for (uint32_t row = first; row < end; ++row) {
                        for (uint32_t col = 0; col < w; ++col) *out++ = float(row * 1000 + col);
                      }
                      ++bands_;
                    });
    upload.addBuffer(*buffer_, words_.data(), words_.size() * 4);
  }

  // Reads both back and checks every texel and word.
  void expectArrivedWhole() {
    Buffer imageBack(device(), w * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::Readback);
    Buffer bufferBack(device(), words_.size() * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                      MemoryIntent::Readback);
    submitAndWait(device(), [&](VkCommandBuffer cmd) {
      transitionImage(cmd, *image_, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
      VkBufferImageCopy region{};
      region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      region.imageExtent = {w, h, 1};
      vkCmdCopyImageToBuffer(cmd, image_->handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                             imageBack.handle(), 1, &region);
      const VkBufferCopy copy{0, 0, words_.size() * 4};
      vkCmdCopyBuffer(cmd, buffer_->handle(), bufferBack.handle(), 1, &copy);
    });
    std::vector<float> pixels(w * h);
    imageBack.read(pixels.data(), pixels.size() * 4);
    for (uint32_t row = 0; row < h; ++row) {
      for (uint32_t col = 0; col < w; ++col) {
        ASSERT_EQ(pixels[row * w + col], float(row * 1000 + col)) << row << "," << col;
      }
    }
    std::vector<uint32_t> back(words_.size());
    bufferBack.read(back.data(), back.size() * 4);
    EXPECT_EQ(back, words_);
  }

  std::unique_ptr<Image> image_;
  std::vector<uint32_t> words_ = std::vector<uint32_t>(1000);
  std::unique_ptr<Buffer> buffer_;
  int bands_ = 0;
};

TEST_F(Upload, ImagesAndBuffersArriveWholeThroughATinyStagingBuffer) {
  // 512 bytes of staging: three rows of the image at a time, the buffer in
  // eight pieces, so many submissions.
  UploadBatch upload(device(), 512);
  add(upload);
  upload.submit();
  EXPECT_GE(bands_, 8);
  expectArrivedWhole();
}

// recordShare: a share of 512 bytes at a time, each in a submission of its
// own (a frame's commands), arrives as whole as one submit().
TEST_F(Upload, SharesRecordedFrameByFrameArriveWhole) {
  UploadBatch upload(device());
  add(upload);
  const size_t total = upload.bytesLeft();
  // Each piece rounded up to 16 bytes in the staging buffer.
  EXPECT_EQ(total, (size_t{w} * h * 4 + 15) / 16 * 16 + words_.size() * 4);
  int shares = 0;
  bool done = false;
  while (!done) {
    const size_t before = upload.bytesLeft();
    submitAndWait(device(), [&](VkCommandBuffer cmd) { done = upload.recordShare(cmd, 512); });
    ++shares;
    ASSERT_LT(upload.bytesLeft(), before) << "a share made no progress";
    ASSERT_LT(shares, 100);
  }
  EXPECT_GE(shares, int(total / 512));
  EXPECT_EQ(upload.bytesLeft(), 0u);
  expectArrivedWhole();
  // An empty batch is done at once and records nothing.
  submitAndWait(device(), [&](VkCommandBuffer cmd) { EXPECT_TRUE(upload.recordShare(cmd, 512)); });
}

}  // namespace
}  // namespace aal
