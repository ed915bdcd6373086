#include "aperture/engine/terrain_renderer.h"

#include <chrono>
#include <stdexcept>
#include <string>

#include <Imath/half.h>

#include "aperture/engine/frame_uniforms.h"
#include "aperture/engine/passes/frame_passes.h"
#include "aperture/engine/passes/pass_pipelines.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/frames_in_flight.h"
#include "aperture/engine/vk/serial_pass_timer.h"

namespace aal {

bool isDebugMode(ShadingMode mode) {
  return mode == ShadingMode::DebugVisible || mode == ShadingMode::DebugBentNormal ||
         mode == ShadingMode::DebugSunFraction || mode == ShadingMode::DebugSkyFill ||
         mode == ShadingMode::DebugObscurance || mode == ShadingMode::DebugTransfer;
}

TerrainRenderer::TerrainRenderer(const Device& device, uint32_t width, uint32_t height,
                                 VkFormat displayFormat)
    : device_(device),
      width_(width),
      height_(height),
      hdr_(device, {width, height, kHdrFormat,
                    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                        VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT}),
      depth_(device, {width, height, kDepthFormat,
                      VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                      VK_IMAGE_ASPECT_DEPTH_BIT}),
      display_(device, {width, height, displayFormat,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                            VK_IMAGE_USAGE_SAMPLED_BIT}),
      ambient_(device, {width, height, kAmbientFormat,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      surface_(device, {width, height, kSurfaceFormat,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      transfer_(device, {width, height, kTransferFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      filtered_(device, {width, height, kTransferFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      skyTable_(device, {AAL_SKY_LUT_WIDTH, AAL_SKY_LUT_HEIGHT, kSkyTableFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      capTable_(device, {AAL_CAP_TABLE_WIDTH, AAL_CAP_TABLE_HEIGHT, kCapTableFormat,
                         VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT}),
      passes_(std::make_unique<PassPipelines>(device, displayFormat)) {
  for (uint32_t i = 0; i < kFramesInFlight; ++i)
    slots_.push_back(std::make_unique<FrameSlot>(device));
  slot_ = slots_.front().get();
}

TerrainRenderer::~TerrainRenderer() = default;

TerrainRenderer::FrameSlot::FrameSlot(const Device& device)
    : uniforms(device, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
               MemoryIntent::Upload),
      samples(device, sizeof(ObscuranceSampleBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
              MemoryIntent::Upload),
      timer(device, 8) {}

TerrainRenderer::FrameSlot& TerrainRenderer::frameSlot(uint32_t index, const char* caller) const {
  if (index >= slots_.size()) {
    throw std::invalid_argument(std::string("TerrainRenderer::") + caller + ": frame slot " +
                                std::to_string(index) + " of " + std::to_string(slots_.size()));
  }
  return *slots_[index];
}

std::vector<std::pair<std::string, double>> TerrainRenderer::passMilliseconds(
    uint32_t index) const {
  return frameSlot(index, "passMilliseconds").timer.results();
}

void TerrainRenderer::record(VkCommandBuffer cmd, const TerrainScene& scene, const FrameSettings& s,
                             const FrameOutput& output) {
  if (!scene.built()) {
    throw std::logic_error(
        "TerrainRenderer::record: the scene's textures are still being sent "
        "(TerrainScene::recordBuildShare)");
  }
  slot_ = &frameSlot(output.frameSlot, "record");
  // The frame before may still be on the device (frames in flight): its
  // reads and writes of the targets and of the slopes (which a spread
  // re-lay rewrites, below) come first.
  waitForEarlierCommands(cmd);
  // Profiled, the host's part is a step of its own.
  const auto wall0 =
      serial_ ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  const double cpu0 = serial_ ? processCpuMs() : 0;
  const FramePlan plan = prepareFrame(cmd, scene, s, output);
  if (serial_) {
    const std::chrono::duration<double, std::milli> wall = std::chrono::steady_clock::now() - wall0;
    serial_->addHost("prepare (host)", wall.count(), processCpuMs() - cpu0);
  }
  const PassContext pass{
      cmd, scene, *passes_, slot_->timer, slot_->uniforms, slot_->patches, slot_->samples};
  const FrameTargets targets = frameTargets();
  // Profiled (profile()): each step submitted on its own.
  const auto step = [&](const char* name) {
    if (serial_) serial_->split(cmd, name);
  };
  slot_->timer.reset(cmd);
  if (plan.capTableUpload) recordCapTableUpload(cmd, capTableStaging_, capTable_);
  recordSkyTable(pass, targets);
  step("sky table");
  readyTerrainTargets(pass, plan, targets);
  recordTerrainPass(pass, plan, targets);
  step(plan.obscurance ? "terrain + sky (G-buffer)" : "terrain + sky");
  if (plan.obscurance) {
    recordObscurance(pass, plan, targets);
    step("obscurance");
    if (plan.interleaved) {
      recordObscuranceFilter(pass, plan, targets);
      step("obscurance filter");
    }
    recordComposite(pass, plan, targets);
    step("composite");
  }
  if (plan.resolve && plan.linear) {
    recordAccumulation(pass, plan, targets);
    step("accumulate");
  }
  // Last: the tone map into the display image, unless a pass wrote it.
  if (plan.linear) {
    recordToneMap(pass, plan, targets);
    step("tone map");
  }
  recordDisplayHandoff(pass, plan, targets);
}

std::vector<SerialPassTimer::Step> TerrainRenderer::profile(const TerrainScene& scene,
                                                            const FrameSettings& s,
                                                            bool serialized) {
  SerialPassTimer serial(device_);
  if (serialized) serial_ = &serial;
  struct Restore {
    SerialPassTimer*& timer;
    ~Restore() { timer = nullptr; }
  } restore{serial_};
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = processCpuMs();
  // The last step (the display's hand-over) is submitted by submitAndWait.
  double splitWall = 0, splitCpu = 0;
  submitAndWait(device_, [&](VkCommandBuffer cmd) {
    record(cmd, scene, s, FrameOutput{});
    for (const SerialPassTimer::Step& step : serial.steps()) {
      splitWall += step.wallMs;
      splitCpu += step.cpuMs;
    }
  });
  const std::chrono::duration<double, std::milli> wall = std::chrono::steady_clock::now() - wall0;
  serial.addHost(serialized ? "display hand-over, recording" : "frame in one submission",
                 wall.count() - splitWall, processCpuMs() - cpu0 - splitCpu);
  DeletionQueue& deletions = device_.deletionQueue();
  deletions.releaseCompleted(deletions.endFrame());
  return serial.steps();
}

FrameTargets TerrainRenderer::frameTargets() const {
  return {.hdr = hdr_,
          .depth = depth_,
          .display = display_,
          .ambient = ambient_,
          .surface = surface_,
          .transfer = transfer_,
          .filtered = filtered_,
          .skyTable = skyTable_,
          .capTable = capTable_,
          .historyMeans = {historyMeans_[0].get(), historyMeans_[1].get()},
          .historyPoints = {historyPoints_[0].get(), historyPoints_[1].get()},
          .resolveHistory = {resolveHistory_[0].get(), resolveHistory_[1].get()}};
}

FrameResult TerrainRenderer::render(const TerrainScene& scene, const FrameSettings& s,
                                    bool wantLinear) {
  return renderHeadless(scene, s, wantLinear, false);
}

FrameResult TerrainRenderer::renderAccumulated(const TerrainScene& scene, const FrameSettings& s,
                                               bool wantLinear) {
  return renderHeadless(scene, s, wantLinear, true);
}

void TerrainRenderer::accumulate(const TerrainScene& scene, const FrameSettings& s) {
  renderHeadless(scene, s, false, true, false);
}

FrameResult TerrainRenderer::renderHeadless(const TerrainScene& scene, const FrameSettings& s,
                                            bool wantLinear, bool temporal, bool readBack) {
  const size_t pixels = size_t(width_) * height_;
  wantLinear = wantLinear && readBack;
  Buffer displayReadback;
  if (readBack) {
    displayReadback =
        Buffer(device_, pixels * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::Readback);
  }
  Buffer linearReadback;
  if (wantLinear) {
    linearReadback =
        Buffer(device_, pixels * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::Readback);
  }

  submitAndWait(device_, [&](VkCommandBuffer cmd) {
    // Accumulated in linear radiance, then tone-mapped.
    record(cmd, scene, s, FrameOutput{.linear = wantLinear || temporal, .temporal = temporal});
    if (readBack) copyImageToBuffer(cmd, display_, displayReadback);
    if (wantLinear) {
      transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
      copyImageToBuffer(cmd, hdr_, linearReadback);
    }
  });
  // The headless frame has completed: what it retired goes now.
  DeletionQueue& deletions = device_.deletionQueue();
  deletions.releaseCompleted(deletions.endFrame());

  FrameResult result;
  result.width = width_;
  result.height = height_;
  if (readBack) {
    result.display.resize(pixels * 4);
    displayReadback.read(result.display.data(), result.display.size());
  }
  if (wantLinear) {
    std::vector<Imath::half> halves(pixels * 4);
    linearReadback.read(halves.data(), halves.size() * sizeof(Imath::half));
    result.linear.assign(halves.begin(), halves.end());
  }
  result.passMilliseconds = slot_->timer.results();
  result.triangles = selection_.triangles;
  result.patchesPerLevel = selection_.patchesPerLevel;
  return result;
}

}  // namespace aal
