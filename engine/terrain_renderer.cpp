#include "aperture/engine/terrain_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include <Imath/half.h>

#include <glm/matrix.hpp>

#include "aperture/engine/frame_uniforms.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/descriptors.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/vk_check.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/cap_table.h"
#include "aperture/terrain/light/obscurance_samples.h"
#include "aperture/terrain/units.h"
#include "aperture/terrain/view/texel_footprint.h"

namespace aal {

namespace {

constexpr VkFormat kHdrFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr VkFormat kSkyTableFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
// The exact mode's cap table: values g in [0, 1] to 1e-3 (docs/caps.md);
// halves would spend half of that on rounding.
constexpr VkFormat kCapTableFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kAmbientFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kSurfaceFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kTransferFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
// Obscurance reuse: means per sample (open, occluders' albedo), and the
// surface point (texel) and sample count they belong to.
constexpr VkFormat kHistoryMeansFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kHistoryPointsFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

// The modes whose picture W changes: the AAL sky fill (docs/design.md §5) and
// the O/W views. The baselines keep their own ambient term.
bool usesTransfer(ShadingMode mode) {
  return mode == ShadingMode::Approx || mode == ShadingMode::Exact ||
         mode == ShadingMode::Horizon || mode == ShadingMode::DebugObscurance ||
         mode == ShadingMode::DebugTransfer;
}

// The unit-radius sample offsets of eq. 8 of Umenhoffer et al., "Efficient
// Methods for Ambient Lighting", 2009, as std140 vec4s, one set per interleave
// cell (set k's sample i at k * AAL_OBSCURANCE_MAX_SAMPLES + i; 8 KiB, within
// lavapipe's 64 KiB uniform buffers).
static_assert(kObscuranceSampleSets == AAL_OBSCURANCE_SAMPLE_SETS);
struct ObscuranceSampleBlock {
  glm::vec4 offsets[AAL_OBSCURANCE_SAMPLE_SETS * AAL_OBSCURANCE_MAX_SAMPLES];
};

VkRenderingAttachmentInfo colorAttachment(const Image& image, bool clear) {
  return {.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
          .imageView = image.view(),
          .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
          .loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_DONT_CARE,
          .storeOp = VK_ATTACHMENT_STORE_OP_STORE};
}

// Begins dynamic rendering into `colorCount` colour (and an optional depth)
// attachments covering the whole target, with the viewport and scissor set to
// match.
void beginRendering(VkCommandBuffer cmd, uint32_t width, uint32_t height,
                    const VkRenderingAttachmentInfo* colors, uint32_t colorCount,
                    const VkRenderingAttachmentInfo* depth) {
  const VkRect2D area{.offset = {0, 0}, .extent = {width, height}};
  const VkRenderingInfo info{.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                             .renderArea = area,
                             .layerCount = 1,
                             .colorAttachmentCount = colorCount,
                             .pColorAttachments = colors,
                             .pDepthAttachment = depth};
  vkCmdBeginRendering(cmd, &info);
  const VkViewport viewport{
      .x = 0, .y = 0, .width = float(width), .height = float(height), .minDepth = 0, .maxDepth = 1};
  const VkRect2D& scissor = area;
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

// Binding of the first descriptor after the terrain textures.
static_assert(AAL_TERRAIN_TILE_PAGES == kTerrainTilePages);
constexpr uint32_t kAfterTerrainTextures = AAL_TERRAIN_TEXTURES_END;

// The image bound as page `page` of a kind: the scene's, its first where
// it has fewer (the shaders never pick them). The horizons' second moments
// (TerrainScene::horizonMomentPages) take the slope kind's pages 2 and 3:
// the slopes are in the heights' pages, two at most (planTerrainTiles), so
// those are never the slopes' (shaders/terrain_textures.glsl,
// terrainHorizonMomentsLod). No binding of their own, so no pipeline's
// layout changes.
const Image& terrainPageImage(const std::vector<Image>& pages, const TerrainScene& scene,
                              uint32_t page) {
  static_assert(kTerrainTilePages == 4);
  const std::vector<Image>& moments = scene.horizonMomentPages();
  if (&pages == &scene.slopePages() && page >= 2 && !moments.empty()) {
    return moments[std::min<size_t>(page - 2, moments.size() - 1)];
  }
  return page < pages.size() ? pages[page] : pages.front();
}

// The frame's uniforms and the scene's texture pages (terrainPageImage).
DescriptorWrites terrainWrites(const Buffer& uniforms, const TerrainScene& scene,
                               VkSampler sampler) {
  DescriptorWrites writes;
  writes.buffer(0, uniforms);
  uint32_t binding = AAL_TERRAIN_TEXTURE_BINDING;
  static_assert(AAL_TERRAIN_TEXTURE_KINDS == 4);
  for (const std::vector<Image>* pages :
       {&scene.heightPages(), &scene.aperturePages(), &scene.albedoPages(), &scene.slopePages()}) {
    for (uint32_t page = 0; page < kTerrainTilePages; ++page) {
      writes.image(binding++, terrainPageImage(*pages, scene, page).view(), sampler);
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

// The constants of shaders/variant.glsl, in AAL_SPEC_* order.
// `footprintProbes`: the terrain pass's most probes (FrameSettings::anisotropy);
// the passes that filter no footprint keep the default.
std::vector<int32_t> variantConstants(ShadingMode mode, int albedoSource, bool display,
                                      int footprintProbes = kMaxFootprintProbes) {
  static_assert(AAL_SPEC_SHADING_MODE == 0 && AAL_SPEC_ALBEDO_SOURCE == 1 &&
                AAL_SPEC_DISPLAY_OUTPUT == 2 && AAL_SPEC_FOOTPRINT_PROBES == 3);
  return {static_cast<int32_t>(mode), albedoSource, display ? 1 : 0, footprintProbes};
}

}  // namespace

bool isDebugMode(ShadingMode mode) {
  return mode == ShadingMode::DebugVisible || mode == ShadingMode::DebugBentNormal ||
         mode == ShadingMode::DebugSunFraction || mode == ShadingMode::DebugSkyFill ||
         mode == ShadingMode::DebugObscurance || mode == ShadingMode::DebugTransfer;
}

// Pipelines are made for the variants frames ask for (shading mode, albedo
// source, display or HDR output, texture paging) and kept: switching modes
// costs one pipeline build the first time (lavapipe: ~0.1-0.3 s).
struct TerrainRenderer::Passes {
  const Device& device;
  VkFormat displayFormat;
  std::map<std::string, std::unique_ptr<GraphicsPipeline>> pipelines;
  GraphicsPipeline skyTable, filter, composite, toneMap, upscale;
  // terrainSampler: the DEM's mipmapped textures (terrain_textures.glsl);
  // skySampler: the sky table, wrapping in azimuth.
  Sampler terrainSampler, nearest, skySampler, linear;

  Passes(const Device& d, VkFormat display)
      : device(d),
        displayFormat(display),
        skyTable(d, {.vertexShader = "fullscreen.vert",
                     .fragmentShader = "sky_lut.frag",
                     .colorFormats = {kSkyTableFormat}}),
        filter(d, {.vertexShader = "fullscreen.vert",
                   .fragmentShader = "obscurance_filter.frag",
                   .colorFormats = {kTransferFormat}}),
        composite(d, {.vertexShader = "fullscreen.vert",
                      .fragmentShader = "composite.frag",
                      .colorFormats = {kHdrFormat},
                      .additiveBlend = true}),
        toneMap(d, {.vertexShader = "fullscreen.vert",
                    .fragmentShader = "tone_map.frag",
                    .colorFormats = {display}}),
        upscale(d, {.vertexShader = "fullscreen.vert",
                    .fragmentShader = "upscale.frag",
                    .colorFormats = {display}}),
        terrainSampler(d, VK_FILTER_LINEAR, true),
        nearest(d, VK_FILTER_NEAREST),
        skySampler(d, VK_FILTER_LINEAR, false, true),
        linear(d, VK_FILTER_LINEAR) {}

  const GraphicsPipeline& cached(const std::string& key, const GraphicsPipelineDesc& desc) {
    std::unique_ptr<GraphicsPipeline>& p = pipelines[key];
    if (!p) p = std::make_unique<GraphicsPipeline>(device, desc);
    return *p;
  }

  // The terrain pass: forward into the display (or HDR) target, or with the
  // obscurance pass into its three targets.
  const GraphicsPipeline& terrain(TexturePaging paging, ShadingMode mode, int albedo, bool gbuffer,
                                  bool display, int footprintProbes) {
    display = display && !gbuffer;
    const std::string key = "terrain/" + std::to_string(int(paging)) + "/" +
                            std::to_string(int(mode)) + "/" + std::to_string(albedo) + "/" +
                            std::to_string(footprintProbes) + "/" +
                            (gbuffer   ? "g"
                             : display ? "d"
                                       : "h");
    std::vector<VkFormat> formats{display ? displayFormat : kHdrFormat};
    // With the obscurance pass the terrain also writes the ambient term and
    // the surface point; without it the frame pays nothing for them.
    if (gbuffer) formats = {kHdrFormat, kAmbientFormat, kSurfaceFormat};
    return cached(key,
                  {.vertexShader = terrainVertexShader(paging),
                   .fragmentShader = terrainFragmentShader(paging, gbuffer),
                   .colorFormats = formats,
                   .depthFormat = kDepthFormat,
                   .depthTest = true,
                   .depthWrite = true,
                   .specialization = variantConstants(mode, albedo, display, footprintProbes)});
  }

  // The solid base, drawn in the terrain's rendering with the terrain's
  // bindings (its vertex shader reads the heights at the DEM's edge); with
  // the G-buffer it writes "no surface" to the other targets itself.
  const GraphicsPipeline& base(TexturePaging paging, ShadingMode mode, bool gbuffer, bool display) {
    display = display && !gbuffer;
    const bool paged = paging == TexturePaging::All;
    const std::string key = std::string("base/") + (paged ? "p/" : "1/") +
                            std::to_string(int(mode)) +
                            (gbuffer   ? "/g"
                             : display ? "/d"
                                       : "/h");
    std::vector<VkFormat> formats{display ? displayFormat : kHdrFormat};
    if (gbuffer) formats = {kHdrFormat, kAmbientFormat, kSurfaceFormat};
    return cached(key, {.vertexShader = paged ? "base_paged.vert" : "base.vert",
                        .fragmentShader = gbuffer ? "base_gbuffer.frag" : "base.frag",
                        .colorFormats = formats,
                        .depthFormat = kDepthFormat,
                        .depthTest = true,
                        .depthWrite = true,
                        .cullMode = VK_CULL_MODE_BACK_BIT,
                        .specialization = variantConstants(mode, 0, display)});
  }

  // The sky, after the terrain at the far plane with the depth test on, so
  // only the pixels the terrain left empty run its shader; with the
  // G-buffer in the same rendering (one rendering fewer: lavapipe loads and
  // stores its targets at each), writing only the colour.
  const GraphicsPipeline& sky(ShadingMode mode, bool display, bool gbuffer) {
    const std::string key =
        "sky/" + std::to_string(int(mode)) + (display ? "/d" : "/h") + (gbuffer ? "/g" : "");
    std::vector<VkFormat> formats{display ? displayFormat : kHdrFormat};
    if (gbuffer) formats = {kHdrFormat, kAmbientFormat, kSurfaceFormat};
    return cached(key, {.vertexShader = "fullscreen.vert",
                        .fragmentShader = "sky.frag",
                        .colorFormats = formats,
                        .depthFormat = kDepthFormat,
                        .depthTest = true,
                        .specialization = variantConstants(mode, 0, display),
                        .writtenColors = 1u});
  }

  // The composite writing display values (the mode decides raw or tone-mapped).
  const GraphicsPipeline& compositeDisplay(ShadingMode mode) {
    return cached("composite/" + std::to_string(int(mode)),
                  {.vertexShader = "fullscreen.vert",
                   .fragmentShader = "composite_display.frag",
                   .colorFormats = {displayFormat},
                   .specialization = variantConstants(mode, 0, true)});
  }

  // The obscurance pass reads heights and albedo, never apertures.
  // `temporal`: the variant that reads and writes the history of samples.
  const GraphicsPipeline& obscurance(TexturePaging paging, ShadingMode mode, int albedo,
                                     bool temporal) {
    const bool paged = paging == TexturePaging::All;
    const std::string key = std::string("obscurance/") + (paged ? "p/" : "1/") +
                            (temporal ? "t/" : "") + std::to_string(int(mode)) + "/" +
                            std::to_string(albedo);
    std::vector<VkFormat> formats{kTransferFormat};
    if (temporal) formats.insert(formats.end(), {kHistoryMeansFormat, kHistoryPointsFormat});
    const char* shader =
        temporal ? (paged ? "obscurance_temporal_paged.frag" : "obscurance_temporal.frag")
                 : (paged ? "obscurance_paged.frag" : "obscurance.frag");
    return cached(key, {.vertexShader = "fullscreen.vert",
                        .fragmentShader = shader,
                        .colorFormats = formats,
                        .specialization = variantConstants(mode, albedo, false)});
  }
};

namespace {

// The solid base (shaders/base_vertex.glsl): for every drawn patch or
// quadrant of `selection` whose edge lies on the DEM's edge, the wall quads
// under that edge, whose tops are the terrain's edge vertices; then the
// bottom. A patch grid line is drawn as the quads from `first` to `last`
// along it, with the patch as the instance.
void drawBase(VkCommandBuffer cmd, const LodSelection& selection, glm::vec2 demSize) {
  constexpr uint32_t n = kLodPatchQuads, half = n / 2;
  const auto line = [&](uint32_t patch, uint32_t index, uint32_t first, uint32_t last) {
    vkCmdDraw(cmd, (last - first) * 6, 1, index * AAL_BASE_LINE_VERTICES + first * 6, patch);
  };
  // The DEM's last column and row: patches reaching beyond them are clamped
  // onto them (lodPatchTexel), so their edge is the grid line that reaches them.
  const float lastColumn = demSize.x - 1.0f, lastRow = demSize.y - 1.0f;
  uint32_t patch = 0;
  const auto piece = [&](uint32_t c0, uint32_t r0, uint32_t size) {
    const glm::vec4 node = selection.patches[patch].node;
    const float x0 = node.x + float(c0) * node.z, x1 = node.x + float(c0 + size) * node.z;
    const float y0 = node.y + float(r0) * node.z, y1 = node.y + float(r0 + size) * node.z;
    // (A piece folded onto the edge entirely draws nothing of its own.)
    if (x0 < lastColumn && y0 < lastRow) {
      if (y0 == 0.0f) line(patch, r0 / half, c0, c0 + size);                     // north: row r0
      if (y1 >= lastRow) line(patch, (r0 + size) / half, c0, c0 + size);         // south
      if (x0 == 0.0f) line(patch, 3 + c0 / half, r0, r0 + size);                 // west: column c0
      if (x1 >= lastColumn) line(patch, 3 + (c0 + size) / half, r0, r0 + size);  // east
    }
    ++patch;
  };
  for (uint32_t i = 0; i < selection.wholeCount; ++i) piece(0, 0, n);
  for (uint32_t q = 0; q < 4; ++q) {
    for (uint32_t i = 0; i < selection.quadrantCount[q]; ++i)
      piece((q & 1) * half, (q >> 1) * half, half);
  }
  vkCmdDraw(cmd, 6, 1, 6 * AAL_BASE_LINE_VERTICES, 0);
}

}  // namespace

TerrainRenderer::TerrainRenderer(const Device& device, uint32_t width, uint32_t height,
                                 VkFormat displayFormat)
    : device_(device),
      width_(width),
      height_(height),
      hdr_(device, {width, height, kHdrFormat,
                    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                        VK_IMAGE_USAGE_TRANSFER_SRC_BIT}),
      depth_(device, {width, height, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
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
      capTableStaging_(device, size_t{AAL_CAP_TABLE_WIDTH} * AAL_CAP_TABLE_HEIGHT * sizeof(float),
                       VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryIntent::Upload),
      uniforms_(device, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                MemoryIntent::Upload),
      samples_(device, sizeof(ObscuranceSampleBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
               MemoryIntent::Upload),
      passes_(std::make_unique<Passes>(device, displayFormat)),
      timer_(device, 8) {}

TerrainRenderer::~TerrainRenderer() = default;

void TerrainRenderer::prepareHistory(VkCommandBuffer cmd) {
  if (!historyMeans_[0]) {
    for (int i = 0; i < 2; ++i) {
      const VkImageUsageFlags usage =
          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
      historyMeans_[i] =
          std::make_unique<Image>(device_, ImageDesc{width_, height_, kHistoryMeansFormat, usage});
      historyPoints_[i] =
          std::make_unique<Image>(device_, ImageDesc{width_, height_, kHistoryPointsFormat, usage});
      // Read before anything was written: sampled, never used (the history
      // is not valid yet).
      transitionImage(cmd, *historyMeans_[i], VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      transitionImage(cmd, *historyPoints_[i], VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
  }
  const int write = 1 - historyRead_;
  transitionImage(cmd, *historyMeans_[write], VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  transitionImage(cmd, *historyPoints_[write], VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
}

void TerrainRenderer::updateCapTable(VkCommandBuffer cmd, const FrameSettings& s) {
  // Other modes only need a valid image behind the binding: the first frame
  // makes one, and the exact mode remakes it for its sun.
  // The tools allow suns of 0.01 to 20 degrees; the table wants (0, pi/2).
  const float radius = std::clamp(s.lighting.sunRadiusRad, 1e-6f, 1.5f);
  const bool wanted = s.mode == ShadingMode::Exact || capTableRadius_ == 0.0f;
  if (!wanted || radius == capTableRadius_) return;
  const CapIntersectionTable table = makeCapIntersectionTable(radius);
  // The previous frame's submission has finished (see record()): the staging
  // buffer and the image are free.
  capTableStaging_.write(table.values.data(), table.values.size() * sizeof(float));
  transitionImage(cmd, capTable_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  const VkBufferImageCopy region{
      .imageSubresource = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT,
                           .mipLevel = 0,
                           .baseArrayLayer = 0,
                           .layerCount = 1},
      .imageExtent = {.width = AAL_CAP_TABLE_WIDTH, .height = AAL_CAP_TABLE_HEIGHT, .depth = 1}};
  vkCmdCopyBufferToImage(cmd, capTableStaging_.handle(), capTable_.handle(),
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  transitionImage(cmd, capTable_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  capTableRadius_ = radius;
}

int TerrainRenderer::albedoSourceOf(const TerrainScene& scene, const FrameSettings& s) {
  return s.albedoValue       ? AAL_ALBEDO_CONSTANT
         : scene.hasAlbedo() ? AAL_ALBEDO_IMAGE
                             : AAL_ALBEDO_PALETTE;
}

bool TerrainRenderer::writeUniforms(const TerrainScene& scene, const FrameSettings& s) {
  const double aspect = double(extent_.width) / double(extent_.height);
  // The depth range must hold the whole DEM: approximate it from the box.
  const glm::vec4 dem = scene.demInfo();  // width, height (texels), cell size x, y (m)
  const double bottom = scene.minHeight() - (s.base ? double(s.base->depthM) : 0.0);
  const DepthRange range = depthRangeFor(s.camera, {(dem.x - 1.0) * dem.z, (dem.y - 1.0) * dem.w},
                                         bottom, scene.maxHeight());

  FrameUniforms u;
  u.viewProj = projectionMatrix(s.camera, aspect, range) * viewMatrix(s.camera);
  viewProj_ = u.viewProj;
  u.invViewProj = glm::inverse(u.viewProj);
  u.previousViewProj = previousViewProj_;
  u.cameraPos = glm::vec3(s.camera.position);
  u.pixelAngle =
      float(2.0 * std::tan(0.5 * s.camera.verticalFovDeg * kPi / 180.0) / extent_.height);

  const Lighting& light = s.lighting;
  u.sunDirection = light.sunDirection;
  u.sunRadiusRad = light.sunRadiusRad;
  u.sunIrradiance = light.sunIrradiance;
  u.hazeDensityPerM = light.hazeDensityPerM;
  u.skyRadiance = light.skyRadiance;
  u.exposure = light.exposure;
  u.sky = light.sky;

  u.demSize = {dem.x, dem.y};
  u.cellSizeM = {dem.z, dem.w};
  u.minHeightM = scene.minHeight();
  u.maxHeightM = scene.maxHeight();
  u.waterLevelM = s.waterLevelM.value_or(0.0f);
  u.hasWater = s.waterLevelM ? 1 : 0;
  u.albedoValue = s.albedoValue.value_or(glm::vec3(0.0f));
  u.backgroundAlpha = s.transparentBackground ? 0.0f : 1.0f;
  if (s.base) {
    u.baseAlbedo = s.base->albedo;
    u.baseBottomM = float(bottom);
  }

  u.extent = glm::ivec2(glm::uvec2(extent_.width, extent_.height));
  u.previousExtent = glm::ivec2(glm::uvec2(previousExtent_.width, previousExtent_.height));
  u.rawOutput = isDebugMode(s.mode) ? 1 : 0;
  const ObscuranceSettings& o = s.obscurance;
  const bool obscurance = o.enabled && usesTransfer(s.mode);
  if (obscurance) {
    u.obscuranceRadiusM =
        o.radiusM > 0
            ? o.radiusM
            : defaultObscuranceRadiusM({dem.z, dem.w}, {(dem.x - 1) * dem.z, (dem.y - 1) * dem.w});
    u.obscuranceSamples = o.samples;
    u.obscuranceSteps = o.steps;
    u.obscuranceInterleaved = o.interleaved ? 1 : 0;
    u.obscurancePixelSize = o.halfResolution ? 2 : 1;
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
  if (obscurance && o.history != ObscuranceSettings::History::None) {
    // The samples kept from the previous frame belong to the same terrain,
    // settings and occluders' albedo, or to nothing.
    const HistoryKey key{scene.id(),
                         u.obscuranceRadiusM,
                         o.samples,
                         o.steps,
                         o.interleaved,
                         o.halfResolution,
                         albedoSourceOf(scene, s),
                         s.albedoValue.value_or(glm::vec3(-1.0f))};
    historyValid_ = historyValid_ && key == historyKey_;
    historyKey_ = key;
    u.historyValid = historyValid_ ? 1 : 0;
    if (historyValid_ && o.history == ObscuranceSettings::History::Reuse) {
      u.historySubset = int(historySubset_++ % AAL_OBSCURANCE_SUBSETS);
    }
  } else {
    historyValid_ = false;
  }

  const TerrainTileLayout& tiles = scene.tiles();
  u.tileCoreSize = glm::ivec2(glm::uvec2(tiles.coreWidth, tiles.coreHeight));
  u.tileCount = glm::ivec2(glm::uvec2(tiles.tilesX, tiles.tilesY));
  u.tileImageSize = glm::ivec2(glm::uvec2(tiles.imageWidth(), tiles.imageHeight()));
  u.tileBorder = int32_t(tiles.border);
  u.heightLayersPerPage = int32_t(tiles.layersPerPage[0]);
  u.apertureLayersPerPage = int32_t(tiles.layersPerPage[1]);
  u.albedoLayersPerPage = int32_t(tiles.layersPerPage[2]);
  if (s.mode == ShadingMode::Horizon && scene.hasHorizons()) {
    // What B and A hold serves this sun (record() re-laid first): the pair's
    // weights, or the shared direction alone while a re-lay is under way.
    const std::array<float, 2> w = horizonChannelWeights(
        scene.horizonDirections(), scene.horizonChannels(), sunAzimuthRad(u.sunDirection));
    u.horizonWeights = glm::vec2(w[0], w[1]);
  }
  uniforms_.write(&u, sizeof u);
  return obscurance;
}

void TerrainRenderer::selectPatches(const TerrainScene& scene, const FrameSettings& s) {
  LodFrame frame;
  frame.cameraM = s.camera.position;
  frame.viewProj = viewProj_;
  frame.viewportHeightPx = extent_.height;
  frame.verticalFovDeg = s.camera.verticalFovDeg;
  frame.triangleBudget = scene.triangleBudget();
  frame.budgetErrorScale = scene.lodBudgetErrorScale();
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

void TerrainRenderer::record(VkCommandBuffer cmd, const TerrainScene& scene, const FrameSettings& s,
                             const FrameOutput& output) {
  const float scale = std::clamp(output.resolutionScale, 0.05f, 1.0f);
  if (scale < 1.0f && (output.image == VK_NULL_HANDLE || output.linear)) {
    throw std::invalid_argument(
        "TerrainRenderer::record: a reduced resolution needs an output image, not linear output");
  }
  extent_ = {std::max(1u, static_cast<uint32_t>(std::lround(width_ * scale))),
             std::max(1u, static_cast<uint32_t>(std::lround(height_ * scale)))};
  if (s.mode == ShadingMode::Horizon && scene.hasHorizons()) {
    // The slope texture must hold the horizons of the two directions beside
    // the sun: re-lay when the sun leaves the pair on the device, at once or
    // this frame's share of a spread re-lay (engine/horizon_relay.h). Safe
    // here: the previous frame's submission has finished (as writeUniforms
    // below requires; aal-view keeps one frame in flight,
    // engine/vk/frame_sync.h, so no frame still reads the slopes), and the
    // writing waits for itself before this frame's commands are submitted.
    // With more frames in flight this would need the device idle first.
    const int n = scene.horizonDirections();
    const float azimuth = sunAzimuthRad(s.lighting.sunDirection);
    const float motion =
        horizonSunScene_ == scene.id() ? horizonMotionSteps(n, horizonSunAzimuth_, azimuth) : 0.0f;
    HorizonRelayPolicy policy;
    if (s.horizonRelayTexelsPerFrame > 0) {
      policy.bandsPerFrame = uint32_t(std::clamp<uint64_t>(
          s.horizonRelayTexelsPerFrame / scene.horizonBandTexels(), 1, scene.horizonBands()));
    }
    scene.writeHorizonRelay(device_, planHorizonRelay(n, scene.horizonChannels(), azimuth, motion,
                                                      scene.horizonBands(), policy));
    horizonSunScene_ = scene.id();
    horizonSunAzimuth_ = azimuth;
  }
  const bool obscurance = writeUniforms(scene, s);
  selectPatches(scene, s);
  const int albedo = albedoSourceOf(scene, s);
  const TexturePaging paging = texturePagingOf(scene.tiles());
  const bool linear = output.linear;
  // The pass that writes display values: into the output image itself when
  // it is drawn at full size, else into displayImage() (and scaled up).
  const bool external = output.image != VK_NULL_HANDLE && !linear;
  const bool intoOutput = external && extent_.width == width_ && extent_.height == height_;
  VkRenderingAttachmentInfo display = colorAttachment(display_, false);
  if (intoOutput) display.imageView = output.view;
  // Without linear output or the obscurance pass the terrain and the sky
  // write display values at once: no HDR target, no tone-map pass.
  const bool direct = !linear && !obscurance;
  if (s.mode == ShadingMode::Horizon && !scene.hasHorizons()) {
    throw std::invalid_argument(
        "the horizon mode needs the DEM's directional horizons (aal-bake --horizons)");
  }
  timer_.reset(cmd);
  updateCapTable(cmd, s);

  // The sky table for this frame's sun (sky_lut.glsl).
  transitionImage(cmd, skyTable_, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  const VkRenderingAttachmentInfo table = colorAttachment(skyTable_, false);
  timer_.begin(cmd, "sky table");
  beginRendering(cmd, AAL_SKY_LUT_WIDTH, AAL_SKY_LUT_HEIGHT, &table, 1, nullptr);
  passes_->skyTable.bind(cmd, DescriptorWrites().buffer(0, uniforms_), nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  timer_.end(cmd);
  transitionImage(cmd, skyTable_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

  if (intoOutput) {
    transitionImage(cmd, output.image, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  } else {
    transitionImage(cmd, display_, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  }
  if (!direct) {
    transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  }
  if (obscurance) {
    transitionImage(cmd, ambient_, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    transitionImage(cmd, surface_, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  }
  transitionImage(cmd, depth_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);

  // Pass 1 and 2, one rendering: the terrain, then the sky where the terrain
  // left the far plane. With the obscurance pass the terrain also writes
  // what it and the composite read (shaders/terrain_shading.glsl; cleared to
  // "no surface": ambient 0 at distance 0, texel -1), which the sky leaves
  // as they are (its other targets masked off; without independent blend
  // state the sky follows in a second rendering with the colour and depth
  // only).
  const bool skyApart = obscurance && !device_.independentBlend();
  VkRenderingAttachmentInfo colors[3] = {direct ? display : colorAttachment(hdr_, false),
                                         colorAttachment(ambient_, true),
                                         colorAttachment(surface_, true)};
  colors[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  colors[2].clearValue.color = {{-1.0f, -1.0f, 0.0f, 0.0f}};
  VkRenderingAttachmentInfo depth{
      .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
      .imageView = depth_.view(),
      .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
      .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
      .storeOp = skyApart ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE,
      .clearValue = {.depthStencil = {.depth = 1.0f, .stencil = 0}}};
  beginRendering(cmd, extent_.width, extent_.height, colors, obscurance ? 3 : 1, &depth);
  timer_.begin(cmd, "terrain");
  passes_
      ->terrain(paging, s.mode, albedo, obscurance, direct,
                std::clamp(s.anisotropy, 1, kMaxFootprintProbes))
      .bind(cmd,
            terrainWrites(uniforms_, scene, passes_->terrainSampler.handle())
                .buffer(kAfterTerrainTextures, patches_)
                .image(kAfterTerrainTextures + 1, capTable_.view(), passes_->linear.handle()),
            nullptr);
  vkCmdBindIndexBuffer(cmd, scene.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
  drawPatches(cmd);
  if (s.base) {
    passes_->base(paging, s.mode, obscurance, direct)
        .bind(cmd,
              terrainWrites(uniforms_, scene, passes_->terrainSampler.handle())
                  .buffer(kAfterTerrainTextures, patches_),
              nullptr);
    drawBase(cmd, selection_, glm::vec2(scene.demInfo()));
  }
  timer_.end(cmd);
  if (skyApart) {
    vkCmdEndRendering(cmd);
    // Order the terrain's colour and depth writes before the sky's.
    transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    transitionImage(cmd, depth_, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    colors[0].loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    beginRendering(cmd, extent_.width, extent_.height, colors, 1, &depth);
  }
  timer_.begin(cmd, "sky");
  passes_->sky(s.mode, direct, obscurance && !skyApart)
      .bind(cmd,
            DescriptorWrites()
                .buffer(0, uniforms_)
                .image(1, skyTable_.view(), passes_->skySampler.handle()),
            nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  timer_.end(cmd);
  vkCmdEndRendering(cmd);

  if (obscurance) recordObscurance(cmd, scene, s, linear, display);

  // Last: the tone map into the display image, unless a pass wrote it.
  if (linear) {
    transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    beginRendering(cmd, extent_.width, extent_.height, &display, 1, nullptr);
    timer_.begin(cmd, "tone map");
    passes_->toneMap.bind(
        cmd,
        DescriptorWrites().buffer(0, uniforms_).image(1, hdr_.view(), passes_->nearest.handle()),
        nullptr);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    timer_.end(cmd);
    vkCmdEndRendering(cmd);
  }
  if (!intoOutput) {
    transitionImage(cmd, display_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  }
  if (external && !intoOutput) recordUpscale(cmd, output);
  // What the next frame's obscurance reuse reprojects with.
  previousViewProj_ = viewProj_;
  previousExtent_ = extent_;
}

void TerrainRenderer::recordUpscale(VkCommandBuffer cmd, const FrameOutput& output) {
  transitionImage(cmd, display_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, output.image, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  VkRenderingAttachmentInfo target = colorAttachment(display_, false);
  target.imageView = output.view;
  timer_.begin(cmd, "upscale");
  beginRendering(cmd, width_, height_, &target, 1, nullptr);
  passes_->upscale.bind(
      cmd,
      DescriptorWrites().buffer(0, uniforms_).image(1, display_.view(), passes_->linear.handle()),
      nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  timer_.end(cmd);
  transitionImage(cmd, display_, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                  VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

void TerrainRenderer::recordObscurance(VkCommandBuffer cmd, const TerrainScene& scene,
                                       const FrameSettings& frame, bool linear,
                                       const VkRenderingAttachmentInfo& display) {
  const ObscuranceSettings& settings = frame.obscurance;
  transitionImage(cmd, ambient_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, surface_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  transitionImage(cmd, transfer_, VK_IMAGE_LAYOUT_UNDEFINED,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  // At half resolution the pass fills the top-left quarter of transfer_.
  const uint32_t scale = settings.halfResolution ? 2 : 1;
  const uint32_t passWidth = (extent_.width + scale - 1) / scale,
                 passHeight = (extent_.height + scale - 1) / scale;
  const bool temporal = settings.history != ObscuranceSettings::History::None;
  if (temporal) prepareHistory(cmd);
  const int write = 1 - historyRead_;
  VkRenderingAttachmentInfo targets[3] = {colorAttachment(transfer_, false), {}, {}};
  DescriptorWrites writes =
      terrainWrites(uniforms_, scene, passes_->terrainSampler.handle())
          .buffer(kAfterTerrainTextures, samples_)
          .image(kAfterTerrainTextures + 1, surface_.view(), passes_->nearest.handle())
          .image(kAfterTerrainTextures + 2, ambient_.view(), passes_->nearest.handle());
  if (temporal) {
    targets[1] = colorAttachment(*historyMeans_[write], false);
    targets[2] = colorAttachment(*historyPoints_[write], false);
    writes
        .image(kAfterTerrainTextures + 3, historyMeans_[historyRead_]->view(),
               passes_->nearest.handle())
        .image(kAfterTerrainTextures + 4, historyPoints_[historyRead_]->view(),
               passes_->nearest.handle());
  }
  // Timestamps around the whole rendering: lavapipe rasterizes when a
  // rendering ends, so one inside it misses the work.
  timer_.begin(cmd, "obscurance");
  beginRendering(cmd, passWidth, passHeight, targets, temporal ? 3 : 1, nullptr);
  passes_
      ->obscurance(texturePagingOf(scene.tiles()), frame.mode, albedoSourceOf(scene, frame),
                   temporal)
      .bind(cmd, writes, nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  timer_.end(cmd);
  if (temporal) {
    // What this frame wrote is what the next one reads.
    transitionImage(cmd, *historyMeans_[write], VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    transitionImage(cmd, *historyPoints_[write], VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    historyRead_ = write;
    historyValid_ = true;
  }

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
                             .buffer(0, uniforms_)
                             .image(1, transfer_.view(), passes_->nearest.handle()),
                         nullptr);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
    timer_.end(cmd);
    transitionImage(cmd, filtered_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    result = &filtered_;
  }

  DescriptorWrites composite;
  composite.buffer(0, uniforms_)
      .image(1, result->view(), passes_->nearest.handle())
      .image(2, ambient_.view(), passes_->nearest.handle());
  timer_.begin(cmd, "composite");
  if (linear) {
    // Blended onto the terrain pass's colour: order its writes before the
    // blend's reads.
    transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    VkRenderingAttachmentInfo hdr = colorAttachment(hdr_, false);
    hdr.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    beginRendering(cmd, extent_.width, extent_.height, &hdr, 1, nullptr);
    passes_->composite.bind(cmd, composite, nullptr);
  } else {
    // Read with the rest and written as display values: the tone map folded in.
    transitionImage(cmd, hdr_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    beginRendering(cmd, extent_.width, extent_.height, &display, 1, nullptr);
    passes_->compositeDisplay(frame.mode)
        .bind(cmd, composite.image(3, hdr_.view(), passes_->nearest.handle()), nullptr);
  }
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
    record(cmd, scene, s, FrameOutput{.linear = wantLinear});
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
