// The host's part of a frame (TerrainRenderer::prepareFrame): everything that
// changes the scene or the renderer's state happens here, before a command
// is recorded, so the passes (engine/passes/) only record.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <glm/matrix.hpp>

#include "aperture/engine/frame_uniforms.h"
#include "aperture/engine/passes/frame_plan.h"
#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/device.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/cap_table.h"
#include "aperture/terrain/light/obscurance_samples.h"
#include "aperture/terrain/units.h"
#include "aperture/terrain/view/texel_footprint.h"

namespace aal {

namespace {

// The modes whose picture W changes: the AAL sky fill (docs/design.md §5) and
// the O/W views. The baselines keep their own ambient term.
bool usesTransfer(ShadingMode mode) {
  return mode == ShadingMode::Approx || mode == ShadingMode::Exact ||
         mode == ShadingMode::Horizon || mode == ShadingMode::DebugObscurance ||
         mode == ShadingMode::DebugTransfer;
}

// AAL_ALBEDO_* of the frame.
int albedoSourceOf(const TerrainScene& scene, const FrameSettings& s) {
  return s.albedoValue       ? AAL_ALBEDO_CONSTANT
         : scene.hasAlbedo() ? AAL_ALBEDO_IMAGE
                             : AAL_ALBEDO_PALETTE;
}

// Which passes run, at what size, into which targets.
FramePlan planPasses(const TerrainScene& scene, const FrameSettings& s, const FrameOutput& output,
                     VkExtent2D extent, VkExtent2D fullExtent, bool independentBlend) {
  FramePlan plan;
  plan.mode = s.mode;
  plan.albedoSource = albedoSourceOf(scene, s);
  plan.paging = texturePagingOf(scene.tiles());
  plan.footprintProbes = std::clamp(s.anisotropy, 1, kMaxFootprintProbes);
  plan.base = s.base.has_value();
  plan.extent = extent;
  plan.fullExtent = fullExtent;
  plan.linear = output.linear;
  const bool external = output.image != VK_NULL_HANDLE && !output.linear;
  plan.intoOutput =
      external && extent.width == fullExtent.width && extent.height == fullExtent.height;
  plan.upscale = external && !plan.intoOutput;
  plan.outputImage = output.image;
  plan.outputView = output.view;
  const ObscuranceSettings& o = s.obscurance;
  plan.obscurance = o.enabled && usesTransfer(s.mode);
  plan.direct = !plan.linear && !plan.obscurance;
  plan.skyApart = plan.obscurance && !independentBlend;
  if (plan.obscurance) {
    const uint32_t step = o.halfResolution ? 2 : 1;
    plan.obscuranceExtent = {(extent.width + step - 1) / step, (extent.height + step - 1) / step};
    plan.interleaved = o.interleaved;
    plan.temporal = o.history != ObscuranceSettings::History::None;
  }
  return plan;
}

// The temporal reconstruction's jitter of frame `index`, in drawn pixels
// within (-0.5, 0.5): the Halton sequence in bases 2 and 3 (its first 8
// points, then again), which covers a pixel evenly in any run of frames.
glm::vec2 resolveJitter(uint32_t index) {
  const auto halton = [](uint32_t i, uint32_t base) {
    float f = 1.0f, r = 0.0f;
    for (; i > 0; i /= base) {
      f /= float(base);
      r += f * float(i % base);
    }
    return r;
  };
  const uint32_t i = index % 8 + 1;
  return {halton(i, 2) - 0.5f, halton(i, 3) - 0.5f};
}

// `viewProj` with its picture shifted by `jitter` drawn pixels (a
// translation in clip space, in proportion to w).
glm::mat4 jitteredViewProj(const glm::mat4& viewProj, glm::vec2 jitter, VkExtent2D extent) {
  glm::mat4 shift(1.0f);
  shift[3][0] = 2.0f * jitter.x / float(extent.width);
  shift[3][1] = 2.0f * jitter.y / float(extent.height);
  return shift * viewProj;
}

// Rebuilding frames drawn smaller: the share of this frame's sample in a
// rebuilt pixel when it lies on the pixel's centre; shaders/resolve.glsl
// weighs it down with its distance d from there (output pixels), by
// 1 / (1 + 16 d²), about a fifth of a pixel wide: over the jitter's cycle
// each output pixel is given the samples that fall on it, and a centred one
// still keeps half of the history, which carries the other frames' samples.
// Measured on FrameOutputTest's flight (relative RMSE from 2 x 2 points per
// pixel), blending linear values (decoded exactly; squared, as now: 2.30 %):
// 2.29 % (2.27 % with 0.6 and 32, 2.32 % with 0.4 and 16, 2.37 % with 0.5
// and 8); blending display values, before: 2.43 % against 2.89 % with 1
// and 8 (the sample replacing the history), 2.50 % with 0.5 and 8, 2.59 %
// with 1 and 16, 2.62 % with 0.25 and 16, 2.46 % with 0.5 and 32. From 8 x 8
// points (the test's converged picture now): 1.97 % (1.95 % with 0.6 and 32,
// 2.00 % with 0.4 and 16).
constexpr float kRebuildCurrentWeight = 0.5f;
constexpr float kRebuildCentreFalloff = 16.0f;
// Accumulating at full resolution every point weighs the same (the pixel's
// box, as the ray tracer's subpixels): the frames since the history began,
// or since the camera last moved, are averaged, up to kStillFrames of them
// (beyond that a half-float history would no longer take a share in); while
// the camera moves, the history keeps a running mean of about the last
// kMovingFrames, so that it follows what reprojecting cannot restore
// (disocclusion) within a few frames. Only a camera that stands still
// jitters: a moving one moves its points over the terrain by itself,
// steadily, where a jitter would make each frame's points jump within their
// pixels and the running mean flicker with them (measured on jacksboro's pan
// of docs/comparison.md: 1.31 x the ray tracer's shimmer jittered, 0.64 x
// not).
constexpr uint32_t kStillFrames = 64;
constexpr uint32_t kMovingFrames = 8;

void setLighting(FrameUniforms& u, const Lighting& light) {
  u.sunDirection = light.sunDirection;
  u.sunRadiusRad = light.sunRadiusRad;
  u.sunIrradiance = light.sunIrradiance;
  u.hazeDensityPerM = light.hazeDensityPerM;
  u.skyRadiance = light.skyRadiance;
  u.exposure = light.exposure;
  u.sky = light.sky;
}

// The DEM and its surface; `bottom`: the base's bottom (m).
void setSurface(FrameUniforms& u, const TerrainScene& scene, const FrameSettings& s,
                double bottom) {
  const glm::vec4 dem = scene.demInfo();  // width, height (texels), cell size x, y (m)
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
}

void setTiles(FrameUniforms& u, const TerrainTileLayout& tiles) {
  u.tileCoreSize = glm::ivec2(glm::uvec2(tiles.coreWidth, tiles.coreHeight));
  u.tileCount = glm::ivec2(glm::uvec2(tiles.tilesX, tiles.tilesY));
  u.tileImageSize = glm::ivec2(glm::uvec2(tiles.imageWidth(), tiles.imageHeight()));
  u.tileBorder = int32_t(tiles.border);
  u.heightLayersPerPage = int32_t(tiles.layersPerPage[0]);
  u.apertureLayersPerPage = int32_t(tiles.layersPerPage[1]);
  u.albedoLayersPerPage = int32_t(tiles.layersPerPage[2]);
}

}  // namespace

FramePlan TerrainRenderer::prepareFrame(VkCommandBuffer cmd, const TerrainScene& scene,
                                        const FrameSettings& requested, const FrameOutput& output) {
  // The host writes the uniforms, the obscurance samples and the LOD patches
  // into the frame slot's copies (record() picked them), which no frame in
  // flight uses.
  const float scale = std::clamp(output.resolutionScale, 0.05f, 1.0f);
  if (scale < 1.0f && (output.image == VK_NULL_HANDLE || output.linear)) {
    throw std::invalid_argument(
        "TerrainRenderer::record: a reduced resolution needs an output image, not linear output");
  }
  const bool horizon = requested.mode == ShadingMode::Horizon;
  if (horizon && !scene.hasHorizons()) {
    throw std::invalid_argument(
        "the horizon mode needs the DEM's directional horizons (aal-bake --horizons)");
  }
  extent_ = {std::max(1u, static_cast<uint32_t>(std::lround(width_ * scale))),
             std::max(1u, static_cast<uint32_t>(std::lround(height_ * scale)))};
  if (horizon) relayHorizons(scene, requested, cmd);
  // While a jump's pair is laid over frames no band's horizons are sure to
  // be the sun's pair: the frame is drawn in approx, which reads none
  // (engine/horizon_relay.h).
  const bool laying = horizon && scene.horizonChannels().layingPair();
  FrameSettings approx;
  if (laying) {
    approx = requested;
    approx.mode = ShadingMode::Approx;
  }
  const FrameSettings& s = laying ? approx : requested;
  FramePlan plan =
      planPasses(scene, s, output, extent_, {width_, height_}, device_.independentBlend());
  // Rebuilt from frames drawn smaller, or accumulated at full size in
  // linear radiance.
  const bool rebuild = plan.upscale && output.temporal;
  plan.resolve = rebuild || (output.temporal && plan.linear);
  const bool moved =
      !rebuild && plan.resolve && resolveValid_ && resolveScene_ == scene.id() &&
      !resolveRebuilt_ &&
      !(s.camera.position == resolveCamera_.position && s.camera.lookAt == resolveCamera_.lookAt &&
        s.camera.verticalFovDeg == resolveCamera_.verticalFovDeg);
  jitter_ = plan.resolve && !moved ? resolveJitter(jitterIndex_++) : glm::vec2(0.0f);
  writeUniforms(scene, s, plan.obscurance, plan.resolve);
  selectPatches(scene, s);
  plan.selection = &selection_;
  plan.capTableUpload = prepareCapTable(s);
  if (plan.temporal) prepareHistory(plan);
  if (plan.resolve) {
    prepareResolve(plan, scene, rebuild, moved);
    resolveCamera_ = s.camera;
  } else {
    resolveValid_ = false;
  }
  // What the next frame's obscurance reuse reprojects with: where this
  // frame's samples lie, the jitter included.
  previousViewProj_ = jitteredViewProj(viewProj_, jitter_, extent_);
  previousExtent_ = extent_;
  return plan;
}

void TerrainRenderer::relayHorizons(const TerrainScene& scene, const FrameSettings& s,
                                    VkCommandBuffer cmd) {
  // The slope texture must hold the horizons of the two directions beside
  // the sun: re-lay when the sun leaves the pair on the device, at once or
  // this frame's share of a spread re-lay (engine/horizon_relay.h). Safe
  // with frames in flight: a share is recorded into this frame's commands
  // after their first barrier (waitForEarlierCommands), before the passes
  // that read the slopes; a whole re-lay is submitted to the same queue
  // after the frames in flight, its first barrier waiting for their reads
  // (transitionImage), and waited for before this frame's commands are
  // submitted. Its upload buffers and code images are its own.
  const int n = scene.horizonDirections();
  const float azimuth = sunAzimuthRad(s.lighting.sunDirection);
  const float motion =
      horizonSunScene_ == scene.id() ? horizonMotionSteps(n, horizonSunAzimuth_, azimuth) : 0.0f;
  HorizonRelayPolicy policy;
  if (s.horizonRelayTexelsPerFrame > 0) {
    policy.bandsPerFrame = uint32_t(std::clamp<uint64_t>(
        s.horizonRelayTexelsPerFrame / scene.horizonBandTexels(), 1, scene.horizonBands()));
  }
  scene.writeHorizonRelay(
      device_,
      planHorizonRelay(n, scene.horizonChannels(), azimuth, motion, scene.horizonBands(), policy),
      cmd);
  horizonSunScene_ = scene.id();
  horizonSunAzimuth_ = azimuth;
}

void TerrainRenderer::writeUniforms(const TerrainScene& scene, const FrameSettings& s,
                                    bool obscurance, bool rebuilt) {
  const double aspect = double(extent_.width) / double(extent_.height);
  // The depth range must hold the whole DEM: approximate it from the box.
  const glm::vec4 dem = scene.demInfo();  // width, height (texels), cell size x, y (m)
  const double bottom = scene.minHeight() - (s.base ? double(s.base->depthM) : 0.0);
  const DepthRange range = depthRangeFor(s.camera, {(dem.x - 1.0) * dem.z, (dem.y - 1.0) * dem.w},
                                         bottom, scene.maxHeight());

  FrameUniforms u;
  // The float product the passes draw with (its rounding is the stills'),
  // and the double one the reprojections invert.
  viewProj_ = projectionMatrix(s.camera, aspect, range) * viewMatrix(s.camera);
  viewProjD_ = viewProjectionMatrixD(s.camera, aspect, range);
  u.viewProj = jitteredViewProj(viewProj_, jitter_, extent_);
  u.invViewProj = glm::inverse(u.viewProj);
  u.previousViewProj = previousViewProj_;
  u.cameraPos = glm::vec3(s.camera.position);
  u.pixelAngle =
      float(2.0 * std::tan(0.5 * s.camera.verticalFovDeg * kPi / 180.0) / extent_.height);
  setLighting(u, s.lighting);
  setSurface(u, scene, s, bottom);
  u.extent = glm::ivec2(glm::uvec2(extent_.width, extent_.height));
  // Rebuilt at full resolution, the textures are read for the output's
  // pixels, not the drawn ones (the jitter brings their detail in).
  if (rebuilt) u.footprintScale = float(extent_.height) / float(height_);
  u.previousExtent = glm::ivec2(glm::uvec2(previousExtent_.width, previousExtent_.height));
  u.rawOutput = isDebugMode(s.mode) ? 1 : 0;
  setObscurance(u, scene, s, obscurance);
  setTiles(u, scene.tiles());
  if (s.mode == ShadingMode::Horizon && scene.hasHorizons()) {
    // What B and A hold serves this sun (relayHorizons ran first): the pair's
    // weights, or the shared direction alone while a re-lay is under way.
    const std::array<float, 2> w = horizonChannelWeights(
        scene.horizonDirections(), scene.horizonChannels(), sunAzimuthRad(u.sunDirection));
    u.horizonWeights = glm::vec2(w[0], w[1]);
  }
  slot_->uniforms.write(&u, sizeof u);
}

void TerrainRenderer::setObscurance(FrameUniforms& u, const TerrainScene& scene,
                                    const FrameSettings& s, bool obscurance) {
  const ObscuranceSettings& o = s.obscurance;
  if (obscurance) {
    const glm::vec4 dem = scene.demInfo();
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
    slot_->samples.write(&block, sizeof block);
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
  // Drawn smaller (dynamic resolution), the automatic error is the full
  // frame's in the pixels drawn, not its share of the drawn height: the same
  // share would keep every triangle while the pixels fall with the square of
  // the scale, and then the triangles, a few pixels each, cost the frame
  // more than its pixels do (docs/performance.md, "Where a frame's time
  // goes"). An explicit error is in the pixels drawn as it was.
  if (frame.settings.maxErrorPixels <= 0 && extent_.height < height_) {
    frame.settings.maxErrorPixels = lodAutomaticErrorPixels(height_);
  }
  selection_ = selectLodForFrame(scene.lod(), frame);
  // At least one instance, so the buffer exists when nothing is in view.
  const size_t bytes = std::max<size_t>(selection_.patches.size(), 1) * sizeof(LodPatch);
  Buffer& patches = slot_->patches;
  if (patches.size() < bytes) {
    // Grow by half again to avoid a new one every frame. The old buffer is
    // retired, not destroyed: a command recorded before into the same
    // command buffer (the viewer's screenshot records a frame twice) may
    // still read it.
    device_.deletionQueue().retire(
        std::exchange(patches, Buffer(device_, bytes + bytes / 2,
                                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryIntent::Upload)));
  }
  if (!selection_.patches.empty()) {
    patches.write(selection_.patches.data(), selection_.patches.size() * sizeof(LodPatch));
  }
}

bool TerrainRenderer::prepareCapTable(const FrameSettings& s) {
  // Other modes only need a valid image behind the binding: the first frame
  // makes one, and the exact mode remakes it for its sun.
  // The tools allow suns of 0.01 to 20 degrees; the table wants (0, pi/2).
  const float radius = std::clamp(s.lighting.sunRadiusRad, 1e-6f, 1.5f);
  const bool wanted = s.mode == ShadingMode::Exact || capTableRadius_ == 0.0f;
  if (!wanted || radius == capTableRadius_) return false;
  const CapIntersectionTable table = makeCapIntersectionTable(radius);
  // A fresh staging buffer for this frame's copy; the one before is retired,
  // as a frame in flight may still copy from it.
  Buffer staging(device_, table.values.size() * sizeof(float), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                 MemoryIntent::Upload);
  staging.write(table.values.data(), table.values.size() * sizeof(float));
  Buffer before = std::exchange(capTableStaging_, std::move(staging));
  if (before.handle() != VK_NULL_HANDLE) device_.deletionQueue().retire(std::move(before));
  capTableRadius_ = radius;
  return true;
}

void TerrainRenderer::prepareResolve(FramePlan& plan, const TerrainScene& scene, bool rebuild,
                                     bool moved) {
  if (!resolveHistory_[0]) {
    for (auto& image : resolveHistory_) {
      // Accumulated at full size, the history is copied into the HDR target.
      image = std::make_unique<Image>(
          device_, ImageDesc{width_, height_, kResolveHistoryFormat,
                             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT});
    }
  }
  // A rebuilt history holds display values, an accumulated one radiance.
  const bool valid = resolveValid_ && resolveScene_ == scene.id() && resolveRebuilt_ == rebuild;
  // The frames the history holds before this one (accumulating).
  if (!valid) resolveFrames_ = 0;
  if (moved) resolveFrames_ = std::min(resolveFrames_, kMovingFrames - 1);
  const float accumulated = 1.0f / float(resolveFrames_ + 1);
  resolveFrames_ = std::min(resolveFrames_ + 1, kStillFrames - 1);
  plan.resolveRead = resolveRead_;
  plan.resolveConstants = {.reproject = glm::mat4(resolveViewProjD_ * glm::inverse(viewProjD_)),
                           .jitter = jitter_,
                           .currentWeight = rebuild ? kRebuildCurrentWeight : accumulated,
                           .historyValid = valid ? 1 : 0,
                           .centreFalloff = rebuild ? kRebuildCentreFalloff : 0.0f};
  // What this frame writes is what the next one reads.
  resolveRead_ = 1 - resolveRead_;
  resolveValid_ = true;
  resolveScene_ = scene.id();
  resolveRebuilt_ = rebuild;
  resolveViewProjD_ = viewProjD_;
}

void TerrainRenderer::prepareHistory(FramePlan& plan) {
  plan.historyFresh = !historyMeans_[0];
  if (plan.historyFresh) {
    for (int i = 0; i < 2; ++i) {
      const VkImageUsageFlags usage =
          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
      historyMeans_[i] =
          std::make_unique<Image>(device_, ImageDesc{width_, height_, kHistoryMeansFormat, usage});
      historyPoints_[i] =
          std::make_unique<Image>(device_, ImageDesc{width_, height_, kHistoryPointsFormat, usage});
    }
  }
  plan.historyRead = historyRead_;
  plan.historyWrite = 1 - historyRead_;
  // What this frame writes is what the next one reads.
  historyRead_ = plan.historyWrite;
  historyValid_ = true;
}

}  // namespace aal
