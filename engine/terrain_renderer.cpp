#include "terrain_renderer.h"

#include <algorithm>

#include <Imath/half.h>

#include <glm/matrix.hpp>

#include "commands.h"
#include "descriptors.h"
#include "device.h"
#include "frame_uniforms.h"
#include "obscurance_samples.h"
#include "terrain_scene.h"
#include "vk_check.h"

namespace aal {

namespace {

constexpr VkFormat kHdrFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr VkFormat kDisplayFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kAmbientFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kSurfaceFormat = VK_FORMAT_R32G32_SFLOAT;
constexpr VkFormat kTransferFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

bool isDebug(ShadingMode mode) {
  return mode == ShadingMode::DebugVisible || mode == ShadingMode::DebugBentNormal ||
         mode == ShadingMode::DebugSunFraction || mode == ShadingMode::DebugSkyFill ||
         mode == ShadingMode::DebugObscurance || mode == ShadingMode::DebugTransfer;
}

// The modes whose picture W changes: the AAL sky fill (DESIGN §5) and the O/W
// views. The baselines keep their own ambient term.
bool usesTransfer(ShadingMode mode) {
  return mode == ShadingMode::Approx || mode == ShadingMode::Exact ||
         mode == ShadingMode::DebugObscurance || mode == ShadingMode::DebugTransfer;
}

// The unit-radius sample offsets of seed 000 eq. 8 as std140 vec4s, one set
// per interleave cell (set k's sample i at k * AAL_OBSCURANCE_MAX_SAMPLES + i;
// 8 KiB, within lavapipe's 64 KiB uniform buffers).
static_assert(kObscuranceSampleSets == AAL_OBSCURANCE_SAMPLE_SETS);
struct ObscuranceSampleBlock {
  glm::vec4 offsets[AAL_OBSCURANCE_SAMPLE_SETS * AAL_OBSCURANCE_MAX_SAMPLES];
};

VkRenderingAttachmentInfo colorAttachment(const Image& image, bool clear) {
  VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  a.imageView = image.view();
  a.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  a.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  return a;
}

// Begins dynamic rendering into `colorCount` colour (and an optional depth)
// attachments covering the whole target, with the viewport and scissor set to
// match.
void beginRendering(VkCommandBuffer cmd, uint32_t width, uint32_t height,
                    const VkRenderingAttachmentInfo* colors, uint32_t colorCount,
                    const VkRenderingAttachmentInfo* depth) {
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = {{0, 0}, {width, height}};
  info.layerCount = 1;
  info.colorAttachmentCount = colorCount;
  info.pColorAttachments = colors;
  info.pDepthAttachment = depth;
  vkCmdBeginRendering(cmd, &info);
  const VkViewport viewport{0, 0, float(width), float(height), 0, 1};
  const VkRect2D scissor{{0, 0}, {width, height}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

// The frame's uniforms at binding 0, the terrain textures
// (shaders/terrain_textures.glsl: heights, apertures, albedo, each
// kTerrainTilePages pages), then `rest`.
std::vector<VkDescriptorType> terrainBindings(const std::vector<VkDescriptorType>& rest) {
  static_assert(AAL_TERRAIN_TEXTURE_BINDING == 1);
  std::vector<VkDescriptorType> bindings(1 + 3 * kTerrainTilePages,
                                         VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  bindings.insert(bindings.end(), rest.begin(), rest.end());
  return bindings;
}

// Binding of the first descriptor after the terrain textures.
constexpr uint32_t kAfterTerrainTextures = AAL_TERRAIN_TEXTURE_BINDING + 3 * kTerrainTilePages;

// The frame's uniforms and the scene's texture pages; pages the scene does
// not have repeat its first (the shaders never pick them).
DescriptorWrites terrainWrites(const Buffer& uniforms, const TerrainScene& scene,
                               VkSampler sampler) {
  DescriptorWrites writes;
  writes.uniformBuffer(0, uniforms);
  uint32_t binding = AAL_TERRAIN_TEXTURE_BINDING;
  for (const std::vector<Image>* pages :
       {&scene.heightPages(), &scene.aperturePages(), &scene.albedoPages()}) {
    for (uint32_t page = 0; page < kTerrainTilePages; ++page) {
      const Image& image = page < pages->size() ? (*pages)[page] : pages->front();
      writes.sampledImage(binding++, image.view(), sampler);
    }
  }
  return writes;
}

// Which shader variants sample a scene's textures
// (shaders/terrain_textures.glsl): page 0 only, a pick among two or four
// pages for the apertures only, or among four for the apertures and two for
// the heights and albedo. Lavapipe pays
// for every page a fetch could pick, so each scene gets the least its pages
// need.
enum class TexturePaging { OnePage, TwoAperturePages, AperturePages, All };
constexpr int kTexturePagings = 4;

TexturePaging texturePagingOf(const TerrainTileLayout& tiles) {
  if (tiles.pagesOf(TerrainTexture::Height) > 1 || tiles.pagesOf(TerrainTexture::Albedo) > 1) {
    return TexturePaging::All;
  }
  const uint32_t pages = tiles.pagesOf(TerrainTexture::Aperture);
  return pages == 1   ? TexturePaging::OnePage
         : pages == 2 ? TexturePaging::TwoAperturePages
                      : TexturePaging::AperturePages;
}

// The shaders of one TexturePaging.
const char* terrainVertexShader(TexturePaging paging) {
  return paging == TexturePaging::All ? "terrain_paged.vert" : "terrain.vert";
}
const char* terrainFragmentShader(TexturePaging paging, bool gbuffer) {
  switch (paging) {
    case TexturePaging::OnePage: return gbuffer ? "terrain_gbuffer.frag" : "terrain.frag";
    case TexturePaging::TwoAperturePages:
      return gbuffer ? "terrain_gbuffer_aperture_pages2.frag" : "terrain_aperture_pages2.frag";
    case TexturePaging::AperturePages:
      return gbuffer ? "terrain_gbuffer_aperture_pages4.frag" : "terrain_aperture_pages4.frag";
    case TexturePaging::All: break;
  }
  return gbuffer ? "terrain_gbuffer_paged.frag" : "terrain_paged.frag";
}

// The pipelines that sample the DEM's textures, in one TexturePaging's
// shader variants.
struct TerrainSamplingPipelines {
  GraphicsPipeline terrain, terrainGBuffer, obscurance;

  TerrainSamplingPipelines(const Device& device, TexturePaging paging)
      : terrain(device, {terrainVertexShader(paging),
                         terrainFragmentShader(paging, false),
                         terrainBindings({VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}),
                         0,
                         {kHdrFormat},
                         kDepthFormat,
                         true,
                         true,
                         VK_CULL_MODE_NONE}),
        // With the obscurance pass the terrain also writes the ambient term
        // and the surface point; without it the frame pays nothing for them.
        terrainGBuffer(device, {terrainVertexShader(paging),
                                terrainFragmentShader(paging, true),
                                terrainBindings({VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}),
                                0,
                                {kHdrFormat, kAmbientFormat, kSurfaceFormat},
                                kDepthFormat,
                                true,
                                true,
                                VK_CULL_MODE_NONE}),
        // The obscurance pass reads heights and albedo, never apertures.
        obscurance(device,
                   {"fullscreen.vert",
                    paging == TexturePaging::All ? "obscurance_paged.frag" : "obscurance.frag",
                    terrainBindings({VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                                     VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                     VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}),
                    0,
                    {kTransferFormat},
                    VK_FORMAT_UNDEFINED}) {}
};

}  // namespace

struct TerrainRenderer::Passes {
  GraphicsPipeline sky;
  // Per TexturePaging: one page made with the renderer, the others for the
  // first scene that needs them.
  std::unique_ptr<TerrainSamplingPipelines> samplingByPaging[kTexturePagings];
  GraphicsPipeline filter, composite, toneMap;
  // terrainSampler: the DEM's mipmapped textures (terrain_textures.glsl).
  Sampler terrainSampler, nearest;

  // The terrain-sampling pipelines for `scene`.
  const TerrainSamplingPipelines& sampling(const Device& device, const TerrainScene& scene) {
    const TexturePaging paging = texturePagingOf(scene.tiles());
    std::unique_ptr<TerrainSamplingPipelines>& pipelines = samplingByPaging[int(paging)];
    if (!pipelines) pipelines = std::make_unique<TerrainSamplingPipelines>(device, paging);
    return *pipelines;
  }

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
        filter(device,
               {"fullscreen.vert",
                "obscurance_filter.frag",
                {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                0,
                {kTransferFormat},
                VK_FORMAT_UNDEFINED}),
        composite(device,
                  {"fullscreen.vert",
                   "composite.frag",
                   {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                    VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                   0,
                   {kHdrFormat},
                   VK_FORMAT_UNDEFINED,
                   false,
                   false,
                   VK_CULL_MODE_NONE,
                   true}),
        toneMap(device,
                {"fullscreen.vert",
                 "tone_map.frag",
                 {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                 0,
                 {kDisplayFormat},
                 VK_FORMAT_UNDEFINED}),
        terrainSampler(device, VK_FILTER_LINEAR, true),
        nearest(device, VK_FILTER_NEAREST) {
    samplingByPaging[int(TexturePaging::OnePage)] =
        std::make_unique<TerrainSamplingPipelines>(device, TexturePaging::OnePage);
  }
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
      ambient_(device, {width, height, kAmbientFormat,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      surface_(device, {width, height, kSurfaceFormat,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      transfer_(device, {width, height, kTransferFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      filtered_(device, {width, height, kTransferFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      uniforms_(device, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                MemoryIntent::Upload),
      samples_(device, sizeof(ObscuranceSampleBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
               MemoryIntent::Upload),
      passes_(std::make_unique<Passes>(device)),
      timer_(device, 7) {}

TerrainRenderer::~TerrainRenderer() = default;

bool TerrainRenderer::writeUniforms(const TerrainScene& scene, const FrameSettings& s) {
  const double aspect = double(width_) / double(height_);
  // The depth range must hold the whole DEM: approximate it from the box.
  const glm::vec4 dem = scene.demInfo();
  const DepthRange range = depthRangeFor(s.camera, {(dem.x - 1.0) * dem.z, (dem.y - 1.0) * dem.w},
                                         scene.minHeight(), scene.maxHeight());

  FrameUniforms u;
  u.viewProj = projectionMatrix(s.camera, aspect, range) * viewMatrix(s.camera);
  viewProj_ = u.viewProj;
  u.invViewProj = glm::inverse(u.viewProj);
  u.cameraPos = glm::vec4(glm::vec3(s.camera.position), 1.0f);
  u.sunDirection = glm::vec4(s.sunDirection, s.sunRadiusRad);
  u.sunIrradiance = glm::vec4(s.sunIrradiance, 0.0f);
  u.skyRadiance = glm::vec4(s.skyRadiance, s.hazeDensityPerM);
  u.dem = scene.demInfo();
  u.heights = {scene.minHeight(), scene.maxHeight(), 0.0f, s.waterAtSeaLevel ? 1.0f : 0.0f};
  const int albedoSource = s.albedoValue       ? AAL_ALBEDO_CONSTANT
                           : scene.hasAlbedo() ? AAL_ALBEDO_IMAGE
                                               : AAL_ALBEDO_PALETTE;
  u.grid = {kLodPatchQuads, scene.lod().levels(), static_cast<int>(s.mode), albedoSource};
  u.display = {s.exposure, isDebug(s.mode) ? 1.0f : 0.0f, 0.0f, 0.0f};
  u.albedoValue = glm::vec4(s.albedoValue.value_or(glm::vec3(0.0f)), 0.0f);
  const ObscuranceSettings& o = s.obscurance;
  const bool obscurance = o.enabled && usesTransfer(s.mode);
  if (obscurance) {
    const float radiusM =
        o.radiusM > 0
            ? o.radiusM
            : defaultObscuranceRadiusM({dem.z, dem.w}, {(dem.x - 1) * dem.z, (dem.y - 1) * dem.w});
    u.obscurance = {radiusM, float(o.samples), float(o.steps), 0.0f};
    u.obscurancePass = {1, o.interleaved ? 1 : 0, o.halfResolution ? 2 : 1, 0};
    ObscuranceSampleBlock block{};
    for (int k = 0; k < kObscuranceSampleSets; ++k) {
      const std::vector<glm::vec3>& offsets = obscuranceCellSampleOffsets(o.samples, k);
      for (size_t i = 0; i < offsets.size(); ++i) {
        block.offsets[static_cast<size_t>(k) * AAL_OBSCURANCE_MAX_SAMPLES + i] =
            glm::vec4(offsets[i], 0.0f);
      }
    }
    samples_.write(&block, sizeof block);
  }
  const TerrainTileLayout& tiles = scene.tiles();
  u.tileGrid =
      glm::ivec4(glm::uvec4(tiles.coreWidth, tiles.coreHeight, tiles.tilesX, tiles.tilesY));
  u.tileImage = glm::ivec4(glm::uvec4(tiles.border, 0, tiles.imageWidth(), tiles.imageHeight()));
  u.tileLayers = glm::ivec4(
      glm::uvec4(tiles.layersPerPage[0], tiles.layersPerPage[1], tiles.layersPerPage[2], 0));
  u.sky = s.sky;
  uniforms_.write(&u, sizeof u);
  return obscurance;
}

void TerrainRenderer::selectPatches(const TerrainScene& scene, const FrameSettings& s) {
  LodFrame frame;
  frame.cameraM = s.camera.position;
  frame.viewProj = viewProj_;
  frame.viewportHeightPx = height_;
  frame.verticalFovDeg = s.camera.verticalFovDeg;
  frame.triangleBudget = scene.triangleBudget();
  frame.budgetScaleM = scene.lodBudgetScaleM();
  frame.settings = s.lod;
  selection_ = selectLodForFrame(scene.lod(), frame);
  // At least one instance, so the buffer exists when nothing is in view.
  const size_t bytes = std::max<size_t>(selection_.patches.size(), 1) * sizeof(LodPatch);
  if (patches_.size() < bytes) {
    // The previous frame's submission has finished (see record()): the old
    // buffer may go. Grow by half again to avoid a new one every frame.
    patches_ = Buffer(device_, bytes + bytes / 2, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      MemoryIntent::Upload);
  }
  if (!selection_.patches.empty()) {
    patches_.write(selection_.patches.data(), selection_.patches.size() * sizeof(LodPatch));
  }
}

void TerrainRenderer::drawPatches(VkCommandBuffer cmd) const {
  if (selection_.wholeCount > 0)
    vkCmdDrawIndexed(cmd, kLodPatchIndices, selection_.wholeCount, 0, 0, 0);
  uint32_t first = selection_.wholeCount;
  for (uint32_t q = 0; q < 4; ++q) {
    const uint32_t count = selection_.quadrantCount[q];
    if (count > 0) {
      vkCmdDrawIndexed(cmd, kLodQuadrantIndices, count, q * kLodQuadrantIndices, 0, first);
    }
    first += count;
  }
}

void TerrainRenderer::record(VkCommandBuffer cmd, const TerrainScene& scene,
                             const FrameSettings& s) {
  const bool obscurance = writeUniforms(scene, s);
  selectPatches(scene, s);
  timer_.reset(cmd);
  transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  if (obscurance) {
    transitionImage(cmd, ambient_, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    transitionImage(cmd, surface_, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  }
  transitionImage(cmd, depth_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
  transitionImage(cmd, display_, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);

  // Pass 1 and 2: the terrain, then the sky where the terrain left the far
  // plane. With the obscurance pass the terrain also writes what it and the
  // composite read (shaders/terrain_shading.glsl; cleared to "no surface":
  // ambient 0 at distance 0, texel -1), and the sky follows in a second
  // rendering with the colour and depth only.
  VkRenderingAttachmentInfo colors[3] = {colorAttachment(hdr_, true),
                                         colorAttachment(ambient_, true),
                                         colorAttachment(surface_, true)};
  colors[2].clearValue.color = {{-1.0f, -1.0f, 0.0f, 0.0f}};
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = depth_.view();
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = obscurance ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.clearValue.depthStencil = {1.0f, 0};
  beginRendering(cmd, width_, height_, colors, obscurance ? 3 : 1, &depth);
  timer_.begin(cmd, "terrain");
  const TerrainSamplingPipelines& sampling = passes_->sampling(device_, scene);
  (obscurance ? sampling.terrainGBuffer : sampling.terrain)
      .bind(cmd,
            terrainWrites(uniforms_, scene, passes_->terrainSampler.handle())
                .storageBuffer(kAfterTerrainTextures, patches_),
            nullptr);
  vkCmdBindIndexBuffer(cmd, scene.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
  drawPatches(cmd);
  timer_.end(cmd);
  if (obscurance) {
    vkCmdEndRendering(cmd);
    // Order the terrain's colour and depth writes before the sky's.
    transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    transitionImage(cmd, depth_, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    colors[0].loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    beginRendering(cmd, width_, height_, colors, 1, &depth);
  }
  timer_.begin(cmd, "sky");
  passes_->sky.bind(cmd, DescriptorWrites().uniformBuffer(0, uniforms_), nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  timer_.end(cmd);
  vkCmdEndRendering(cmd);

  if (obscurance) recordObscurance(cmd, scene, s.obscurance);

  // Last pass: tone map into the display image.
  transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  const VkRenderingAttachmentInfo displayColor = colorAttachment(display_, false);
  beginRendering(cmd, width_, height_, &displayColor, 1, nullptr);
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

void TerrainRenderer::recordObscurance(VkCommandBuffer cmd, const TerrainScene& scene,
                                       const ObscuranceSettings& settings) {
  transitionImage(cmd, ambient_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, surface_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, transfer_, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  // At half resolution the pass fills the top-left quarter of transfer_.
  const uint32_t scale = settings.halfResolution ? 2 : 1;
  const uint32_t passWidth = (width_ + scale - 1) / scale,
                 passHeight = (height_ + scale - 1) / scale;
  const VkRenderingAttachmentInfo transfer = colorAttachment(transfer_, false);
  // Timestamps around the whole rendering: lavapipe rasterizes when a
  // rendering ends, so one inside it misses the work.
  timer_.begin(cmd, "obscurance");
  beginRendering(cmd, passWidth, passHeight, &transfer, 1, nullptr);
  passes_->sampling(device_, scene)
      .obscurance.bind(
          cmd,
          terrainWrites(uniforms_, scene, passes_->terrainSampler.handle())
              .uniformBuffer(kAfterTerrainTextures, samples_)
              .sampledImage(kAfterTerrainTextures + 1, surface_.view(), passes_->nearest.handle())
              .sampledImage(kAfterTerrainTextures + 2, ambient_.view(), passes_->nearest.handle()),
          nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  timer_.end(cmd);

  transitionImage(cmd, transfer_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  const Image* result = &transfer_;
  if (settings.interleaved) {
    transitionImage(cmd, filtered_, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    const VkRenderingAttachmentInfo filtered = colorAttachment(filtered_, false);
    timer_.begin(cmd, "obscurance filter");
    beginRendering(cmd, passWidth, passHeight, &filtered, 1, nullptr);
    passes_->filter.bind(cmd,
                         DescriptorWrites()
                             .uniformBuffer(0, uniforms_)
                             .sampledImage(1, transfer_.view(), passes_->nearest.handle()),
                         nullptr);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
    timer_.end(cmd);
    transitionImage(cmd, filtered_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    result = &filtered_;
  }

  // The composite blends onto the terrain pass's colour: order its writes
  // before the blend's reads.
  transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  VkRenderingAttachmentInfo hdr = colorAttachment(hdr_, false);
  hdr.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  timer_.begin(cmd, "composite");
  beginRendering(cmd, width_, height_, &hdr, 1, nullptr);
  passes_->composite.bind(cmd,
                          DescriptorWrites()
                              .uniformBuffer(0, uniforms_)
                              .sampledImage(1, result->view(), passes_->nearest.handle())
                              .sampledImage(2, ambient_.view(), passes_->nearest.handle()),
                          nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  timer_.end(cmd);
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
    copyImageToBuffer(cmd, display_, displayReadback);
    if (wantLinear) {
      transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
      copyImageToBuffer(cmd, hdr_, linearReadback);
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
  result.triangles = selection_.triangles;
  result.patchesPerLevel = selection_.patchesPerLevel;
  return result;
}

}  // namespace aal
