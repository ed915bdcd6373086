#include "terrain_renderer.h"

#include <Imath/half.h>

#include <glm/matrix.hpp>

#include "commands.h"
#include "descriptors.h"
#include "device.h"
#include "frame_uniforms.h"
#include "terrain_scene.h"
#include "vk_check.h"

namespace aal {

namespace {

constexpr VkFormat kHdrFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr VkFormat kDisplayFormat = VK_FORMAT_R8G8B8A8_UNORM;

bool isDebug(ShadingMode mode) {
  return mode == ShadingMode::DebugVisible || mode == ShadingMode::DebugBentNormal ||
         mode == ShadingMode::DebugSunFraction || mode == ShadingMode::DebugSkyFill;
}

VkRenderingAttachmentInfo colorAttachment(const Image& image, bool clear) {
  VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  a.imageView = image.view();
  a.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  a.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  return a;
}

// Begins dynamic rendering into one colour (and optional depth) attachment
// covering the whole target, with the viewport and scissor set to match.
void beginRendering(VkCommandBuffer cmd, uint32_t width, uint32_t height,
                    const VkRenderingAttachmentInfo& color,
                    const VkRenderingAttachmentInfo* depth) {
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = {{0, 0}, {width, height}};
  info.layerCount = 1;
  info.colorAttachmentCount = 1;
  info.pColorAttachments = &color;
  info.pDepthAttachment = depth;
  vkCmdBeginRendering(cmd, &info);
  const VkViewport viewport{0, 0, float(width), float(height), 0, 1};
  const VkRect2D scissor{{0, 0}, {width, height}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

void copyToBuffer(VkCommandBuffer cmd, const Image& image, const Buffer& buffer) {
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {image.desc().width, image.desc().height, 1};
  vkCmdCopyImageToBuffer(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.handle(),
                         1, &region);
}

}  // namespace

struct TerrainRenderer::Passes {
  GraphicsPipeline sky, terrain, toneMap;
  Sampler linear, nearest;

  explicit Passes(const Device& device)
      // The sky is drawn after the terrain, at the far plane with the depth
      // test on, so only the pixels the terrain left empty run its shader.
      : sky(device, {"fullscreen.vert",
                     "sky.frag",
                     {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                     0,
                     {kHdrFormat},
                     kDepthFormat,
                     true,
                     false}),
        terrain(
            device,
            {"terrain.vert",
             "terrain.frag",
             {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
              VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
             0,
             {kHdrFormat},
             kDepthFormat,
             true,
             true,
             VK_CULL_MODE_NONE}),
        toneMap(device,
                {"fullscreen.vert",
                 "tone_map.frag",
                 {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                 0,
                 {kDisplayFormat},
                 VK_FORMAT_UNDEFINED}),
        linear(device, VK_FILTER_LINEAR),
        nearest(device, VK_FILTER_NEAREST) {}
};

TerrainRenderer::TerrainRenderer(const Device& device, uint32_t width, uint32_t height)
    : device_(device),
      width_(width),
      height_(height),
      hdr_(device, {width, height, kHdrFormat,
                    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                        VK_IMAGE_USAGE_TRANSFER_SRC_BIT}),
      depth_(device, {width, height, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                      VK_IMAGE_ASPECT_DEPTH_BIT}),
      display_(device, {width, height, kDisplayFormat,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT}),
      uniforms_(device, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                MemoryIntent::Upload),
      passes_(std::make_unique<Passes>(device)),
      timer_(device, 4) {}

TerrainRenderer::~TerrainRenderer() = default;

void TerrainRenderer::writeUniforms(const TerrainScene& scene, const FrameSettings& s) {
  const double aspect = double(width_) / double(height_);
  // The depth range must hold the whole DEM: approximate it from the box.
  const glm::vec4 dem = scene.demInfo();
  const DepthRange range = depthRangeFor(s.camera, {(dem.x - 1.0) * dem.z, (dem.y - 1.0) * dem.w},
                                         scene.minHeight(), scene.maxHeight());

  FrameUniforms u;
  u.viewProj = projectionMatrix(s.camera, aspect, range) * viewMatrix(s.camera);
  u.invViewProj = glm::inverse(u.viewProj);
  u.cameraPos = glm::vec4(glm::vec3(s.camera.position), 1.0f);
  u.sunDirection = glm::vec4(s.sunDirection, s.sunRadiusRad);
  u.sunIrradiance = glm::vec4(s.sunIrradiance, 0.0f);
  u.skyRadiance = glm::vec4(s.skyRadiance, s.hazeDensityPerM);
  u.dem = scene.demInfo();
  u.heights = {scene.minHeight(), scene.maxHeight(), 0.0f, s.waterAtSeaLevel ? 1.0f : 0.0f};
  u.grid = {scene.gridColumns(), scene.gridRows(), static_cast<int>(s.mode),
            scene.hasAlbedo() ? 1 : 0};
  u.display = {s.exposure, isDebug(s.mode) ? 1.0f : 0.0f, 0.0f, 0.0f};
  u.sky = s.sky;
  uniforms_.write(&u, sizeof u);
}

void TerrainRenderer::record(VkCommandBuffer cmd, const TerrainScene& scene,
                             const FrameSettings& s) {
  writeUniforms(scene, s);
  timer_.reset(cmd);
  transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  transitionImage(cmd, depth_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
  transitionImage(cmd, display_, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);

  // Pass 1 and 2: the terrain, then the sky where the terrain left the far plane.
  VkRenderingAttachmentInfo color = colorAttachment(hdr_, true);
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = depth_.view();
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.clearValue.depthStencil = {1.0f, 0};
  beginRendering(cmd, width_, height_, color, &depth);
  timer_.begin(cmd, "terrain");
  passes_->terrain.bind(cmd,
                        DescriptorWrites()
                            .uniformBuffer(0, uniforms_)
                            .sampledImage(1, scene.heights().view(), passes_->linear.handle())
                            .sampledImage(2, scene.aperture().view(), passes_->linear.handle())
                            .sampledImage(3, scene.albedo().view(), passes_->linear.handle()),
                        nullptr);
  vkCmdBindIndexBuffer(cmd, scene.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
  vkCmdDrawIndexed(cmd, scene.indexCount(), 1, 0, 0, 0);
  timer_.end(cmd);
  timer_.begin(cmd, "sky");
  passes_->sky.bind(cmd, DescriptorWrites().uniformBuffer(0, uniforms_), nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  timer_.end(cmd);
  vkCmdEndRendering(cmd);

  // Pass 3: tone map into the display image.
  transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  beginRendering(cmd, width_, height_, colorAttachment(display_, false), nullptr);
  timer_.begin(cmd, "tone map");
  passes_->toneMap.bind(cmd,
                        DescriptorWrites()
                            .uniformBuffer(0, uniforms_)
                            .sampledImage(1, hdr_.view(), passes_->nearest.handle()),
                        nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  timer_.end(cmd);
  vkCmdEndRendering(cmd);
  transitionImage(cmd, display_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

FrameResult TerrainRenderer::render(const TerrainScene& scene, const FrameSettings& s,
                                    bool wantLinear) {
  const size_t pixels = size_t(width_) * height_;
  Buffer displayReadback(device_, pixels * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         MemoryIntent::Readback);
  Buffer linearReadback;
  if (wantLinear) {
    linearReadback =
        Buffer(device_, pixels * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::Readback);
  }

  submitAndWait(device_, [&](VkCommandBuffer cmd) {
    record(cmd, scene, s);
    copyToBuffer(cmd, display_, displayReadback);
    if (wantLinear) {
      transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
      copyToBuffer(cmd, hdr_, linearReadback);
    }
  });

  FrameResult result;
  result.width = width_;
  result.height = height_;
  result.display.resize(pixels * 4);
  displayReadback.read(result.display.data(), result.display.size());
  if (wantLinear) {
    std::vector<Imath::half> halves(pixels * 4);
    linearReadback.read(halves.data(), halves.size() * sizeof(Imath::half));
    result.linear.assign(halves.begin(), halves.end());
  }
  result.passMilliseconds = timer_.results();
  result.triangles = scene.indexCount() / 3;
  return result;
}

}  // namespace aal
