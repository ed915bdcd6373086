// The frame's pipelines and samplers, and the target formats they are made
// for. Pipelines are made for the variants frames ask for (shading mode,
// albedo source, display or HDR output, texture paging) and kept: switching
// modes costs one pipeline build the first time (lavapipe: ~0.1-0.3 s).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "aperture/engine/vk/graphics_pipeline.h"
#include "aperture/engine/vk/image.h"
#include "aperture/terrain/light/shading.h"

namespace aal {

class Device;
struct TerrainTileLayout;

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
// Temporal reconstruction: the last rebuilt frame's display values, kept in
// halves so that a small change blended in a little at a time is not lost
// to 8-bit rounding.
constexpr VkFormat kResolveHistoryFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

// Which shader variants sample a scene's textures
// (shaders/terrain_textures.glsl): page 0 only, a pick among two or four
// pages for the apertures only, or among four for the apertures and two for
// the heights and albedo. Lavapipe pays
// for every page a fetch could pick, so each scene gets the least its pages
// need.
enum class TexturePaging { OnePage, TwoAperturePages, AperturePages, All };

TexturePaging texturePagingOf(const TerrainTileLayout& tiles);

struct PassPipelines {
  const Device& device;
  VkFormat displayFormat;
  std::map<std::string, std::unique_ptr<GraphicsPipeline>> pipelines;
  GraphicsPipeline skyTable, filter, composite, toneMap, upscale, resolve, resolveLinear;
  // terrainSampler: the DEM's mipmapped textures (terrain_textures.glsl);
  // skySampler: the sky table, wrapping in azimuth.
  Sampler terrainSampler, nearest, skySampler, linear;

  PassPipelines(const Device& d, VkFormat display);

  // The terrain pass: forward into the display (or HDR) target, or with the
  // obscurance pass into its three targets.
  const GraphicsPipeline& terrain(TexturePaging paging, ShadingMode mode, int albedo, bool gbuffer,
                                  bool display, int footprintProbes);
  // The solid base, drawn in the terrain's rendering with the terrain's
  // bindings (its vertex shader reads the heights at the DEM's edge); with
  // the G-buffer it writes "no surface" to the other targets itself.
  const GraphicsPipeline& base(TexturePaging paging, ShadingMode mode, bool gbuffer, bool display);
  // The sky, after the terrain at the far plane with the depth test on, so
  // only the pixels the terrain left empty run its shader; with the
  // G-buffer in the same rendering (one rendering fewer: lavapipe loads and
  // stores its targets at each), writing only the colour.
  const GraphicsPipeline& sky(ShadingMode mode, bool display, bool gbuffer);
  // The composite writing display values (the mode decides raw or tone-mapped).
  const GraphicsPipeline& compositeDisplay(ShadingMode mode);
  // The obscurance pass reads heights and albedo, never apertures.
  // `temporal`: the variant that reads and writes the history of samples.
  const GraphicsPipeline& obscurance(TexturePaging paging, ShadingMode mode, int albedo,
                                     bool temporal);

 private:
  const GraphicsPipeline& cached(const std::string& key, const GraphicsPipelineDesc& desc);
};

}  // namespace aal
