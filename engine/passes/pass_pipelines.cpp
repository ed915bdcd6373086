#include "aperture/engine/passes/pass_pipelines.h"

#include "aperture/engine/passes/frame_plan.h"

#include "aperture/engine/terrain_tiles.h"
#include "aperture/terrain/view/texel_footprint.h"

namespace aal {

namespace {

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

TexturePaging texturePagingOf(const TerrainTileLayout& tiles) {
  if (tiles.pagesOf(TerrainTexture::Height) > 1 || tiles.pagesOf(TerrainTexture::Albedo) > 1) {
    return TexturePaging::All;
  }
  const uint32_t pages = tiles.pagesOf(TerrainTexture::Aperture);
  return pages == 1   ? TexturePaging::OnePage
         : pages == 2 ? TexturePaging::TwoAperturePages
                      : TexturePaging::AperturePages;
}

PassPipelines::PassPipelines(const Device& d, VkFormat display)
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
      resolve(d, {.vertexShader = "fullscreen.vert",
                  .fragmentShader = "resolve.frag",
                  .pushConstantBytes = sizeof(ResolveConstants),
                  .colorFormats = {display, kResolveHistoryFormat}}),
      resolveLinear(d, {.vertexShader = "fullscreen.vert",
                        .fragmentShader = "resolve_linear.frag",
                        .pushConstantBytes = sizeof(ResolveConstants),
                        .colorFormats = {kResolveHistoryFormat}}),
      terrainSampler(d, VK_FILTER_LINEAR, true),
      nearest(d, VK_FILTER_NEAREST),
      skySampler(d, VK_FILTER_LINEAR, false, true),
      linear(d, VK_FILTER_LINEAR) {}

const GraphicsPipeline& PassPipelines::cached(const std::string& key,
                                              const GraphicsPipelineDesc& desc) {
  std::unique_ptr<GraphicsPipeline>& p = pipelines[key];
  if (!p) p = std::make_unique<GraphicsPipeline>(device, desc);
  return *p;
}

const GraphicsPipeline& PassPipelines::terrain(TexturePaging paging, ShadingMode mode, int albedo,
                                               bool gbuffer, bool display, int footprintProbes) {
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
  return cached(key, {.vertexShader = terrainVertexShader(paging),
                      .fragmentShader = terrainFragmentShader(paging, gbuffer),
                      .colorFormats = formats,
                      .depthFormat = kDepthFormat,
                      .depthTest = true,
                      .depthWrite = true,
                      // Back faces are culled when the camera cannot see
                      // them (drawTerrain; docs/rendering.md, "Drawing order").
                      .dynamicCullMode = true,
                      .specialization = variantConstants(mode, albedo, display, footprintProbes)});
}

const GraphicsPipeline& PassPipelines::base(TexturePaging paging, ShadingMode mode, bool gbuffer,
                                            bool display) {
  display = display && !gbuffer;
  const bool paged = paging == TexturePaging::All;
  const std::string key = std::string("base/") + (paged ? "p/" : "1/") + std::to_string(int(mode)) +
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

const GraphicsPipeline& PassPipelines::sky(ShadingMode mode, bool display, bool gbuffer) {
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

const GraphicsPipeline& PassPipelines::compositeDisplay(ShadingMode mode) {
  return cached("composite/" + std::to_string(int(mode)),
                {.vertexShader = "fullscreen.vert",
                 .fragmentShader = "composite_display.frag",
                 .colorFormats = {displayFormat},
                 .specialization = variantConstants(mode, 0, true)});
}

const GraphicsPipeline& PassPipelines::obscurance(TexturePaging paging, ShadingMode mode,
                                                  int albedo, bool temporal) {
  const bool paged = paging == TexturePaging::All;
  const std::string key = std::string("obscurance/") + (paged ? "p/" : "1/") +
                          (temporal ? "t/" : "") + std::to_string(int(mode)) + "/" +
                          std::to_string(albedo);
  std::vector<VkFormat> formats{kTransferFormat};
  if (temporal) formats.insert(formats.end(), {kHistoryMeansFormat, kHistoryPointsFormat});
  const char* shader = temporal
                           ? (paged ? "obscurance_temporal_paged.frag" : "obscurance_temporal.frag")
                           : (paged ? "obscurance_paged.frag" : "obscurance.frag");
  return cached(key, {.vertexShader = "fullscreen.vert",
                      .fragmentShader = shader,
                      .colorFormats = formats,
                      .specialization = variantConstants(mode, albedo, false)});
}

}  // namespace aal
