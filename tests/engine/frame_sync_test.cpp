// FrameSync with the device's DeletionQueue, on the device with the
// validation layer on: a buffer that frame N's commands write, retired while
// frame N is recorded, survives until frame N's fence has been waited for
// and is destroyed then. Destroying it earlier is what the validation layer
// reports (a buffer in use by a pending command buffer), and any message
// fails the test. No window: a submission signals the acquire semaphore and
// one waits on the rendered one, in place of acquire and present. And the
// layer's synchronisation checks, which every Vulkan test has, at work.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/frame_sync.h"
#include "aperture/engine/vk/frames_in_flight.h"
#include "aperture/engine/vk/instance.h"
#include "aperture/engine/vk/vk_check.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

class FrameSyncRetirement : public VulkanTest {
 protected:
  // In place of the swapchain's acquire: signals the frame's semaphore.
  void acquire(VkSemaphore acquired) const {
    const VkSubmitInfo submit{.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                              .signalSemaphoreCount = 1,
                              .pSignalSemaphores = &acquired};
    AAL_VK_CHECK(vkQueueSubmit(device().queue(), 1, &submit, VK_NULL_HANDLE));
  }
  // In place of present: waits for (unsignals) the rendered semaphore.
  void present(VkSemaphore rendered) const {
    const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
    const VkSubmitInfo submit{.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                              .waitSemaphoreCount = 1,
                              .pWaitSemaphores = &rendered,
                              .pWaitDstStageMask = &stage};
    AAL_VK_CHECK(vkQueueSubmit(device().queue(), 1, &submit, VK_NULL_HANDLE));
  }
};

// A buffer whose destruction is logged with the frame it belonged to.
struct LoggedBuffer {
  Buffer buffer;
  std::vector<int>* log = nullptr;
  int frame = 0;
  LoggedBuffer(Buffer b, std::vector<int>& l, int f) : buffer(std::move(b)), log(&l), frame(f) {}
  LoggedBuffer(LoggedBuffer&& o) noexcept
      : buffer(std::move(o.buffer)), log(std::exchange(o.log, nullptr)), frame(o.frame) {}
  LoggedBuffer& operator=(LoggedBuffer&&) = delete;
  ~LoggedBuffer() {
    if (log) log->push_back(frame);
  }
};

TEST_F(FrameSyncRetirement, BufferRetiredInFrameNIsDestroyedWhenFrameNHasCompleted) {
  FrameSync sync(device(), 1);
  std::vector<int> destroyed;
  const int frames = 4 + int(kFramesInFlight);
  for (int frame = 0; frame < frames; ++frame) {
    sync.waitForFrameSlot();
    // The frame kFramesInFlight back has completed and its buffer is gone;
    // the ones of the frames after it are not.
    const int completed = frame - int(kFramesInFlight);
    ASSERT_EQ(destroyed.size(), size_t(std::max(completed + 1, 0))) << "frame " << frame;
    for (int f = 0; f <= completed; ++f) EXPECT_EQ(destroyed[size_t(f)], f);

    acquire(sync.acquired());
    const VkCommandBuffer cmd = sync.beginCommands();
    Buffer buffer(device(), 256, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::DeviceLocal);
    vkCmdFillBuffer(cmd, buffer.handle(), 0, VK_WHOLE_SIZE, uint32_t(frame));
    // Replaced mid-frame, after the frame's commands used it: retired.
    device().deletionQueue().retire(LoggedBuffer(std::move(buffer), destroyed, frame));
    sync.submit(0);
    present(sync.rendered(0));
    EXPECT_EQ(destroyed.size(), size_t(std::max(completed + 1, 0)))
        << "frame " << frame << " destroyed its buffer before it completed";
  }
  // A read-back waits for every submitted frame: all are destroyed.
  sync.waitForSubmittedFrames();
  EXPECT_EQ(destroyed.size(), size_t(frames));
  EXPECT_EQ(device().deletionQueue().pending(), 0u);
}

// The validation layer of every Vulkan test checks synchronisation too
// (engine/vk/instance.cpp): two writes of one buffer with no barrier between
// them are reported.
TEST(Validation, ReportsAWriteAfterAWriteWithoutABarrier) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "no synchronisation checks under AddressSanitizer (engine/vk/instance.cpp)";
#endif
  InstanceOptions options;
  options.validation = true;
  Instance instance(options);
  {
    Device device(instance);
    Buffer buffer(device, 256, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::DeviceLocal);
    submitAndWait(device, [&](VkCommandBuffer cmd) {
      vkCmdFillBuffer(cmd, buffer.handle(), 0, VK_WHOLE_SIZE, 1u);
      vkCmdFillBuffer(cmd, buffer.handle(), 0, VK_WHOLE_SIZE, 2u);
    });
  }
  const std::vector<std::string> messages = instance.validationLog().messages();
  ASSERT_FALSE(messages.empty()) << "the second fill was not reported";
  for (const std::string& message : messages) {
    EXPECT_NE(message.find("SYNC-HAZARD-WRITE-AFTER-WRITE"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace aal
