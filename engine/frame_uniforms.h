// C++ twin of the Frame uniform block of shaders/frame.glsl (std140): the
// same members in the same order. glm's vectors are unaligned, so every
// member sits where std140 puts it only because the block is ordered that
// way (each vec3 followed by a 4-byte scalar, explicit padding before the
// sky); the static_asserts below check each offset, and
// tests/engine/frame_layout_test.cpp checks what the shaders read.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "aperture/shaders/config.h"
#include "aperture/terrain/light/obscurance_samples.h"
#include "aperture/terrain/light/sky_model.h"

namespace aal {

struct FrameUniforms {
  // The camera.
  glm::mat4 viewProj{1.0f};
  glm::mat4 invViewProj{1.0f};
  glm::mat4 previousViewProj{1.0f};
  glm::vec3 cameraPos{0.0f};
  float pixelAngle = 0;

  // The lighting (terrain/light/lighting.h).
  glm::vec3 sunDirection{0.0f};
  float sunRadiusRad = 0;
  glm::vec3 sunIrradiance{0.0f};
  float hazeDensityPerM = 0;
  glm::vec3 skyRadiance{0.0f};
  float exposure = 0;

  // The DEM and its surface.
  glm::vec2 demSize{0.0f};
  glm::vec2 cellSizeM{0.0f};
  float minHeightM = 0;
  float maxHeightM = 0;
  float waterLevelM = 0;
  int32_t hasWater = 0;
  glm::vec3 albedoValue{0.0f};
  float backgroundAlpha = 0;
  glm::vec3 baseAlbedo{0.0f};
  float baseBottomM = 0;

  // Pixels and passes.
  glm::ivec2 extent{0};
  glm::ivec2 previousExtent{0};
  int32_t rawOutput = 0;
  int32_t historySubset = -1;
  int32_t historyValid = 0;
  float obscuranceRadiusM = 0;
  int32_t obscuranceSamples = 0;
  int32_t obscuranceSteps = 0;
  int32_t obscuranceInterleaved = 0;
  int32_t obscurancePixelSize = 0;

  // Tiled terrain textures.
  glm::ivec2 tileCoreSize{0};
  glm::ivec2 tileCount{0};
  glm::ivec2 tileImageSize{0};
  int32_t tileBorder = 0;
  int32_t heightLayersPerPage = 0;
  int32_t apertureLayersPerPage = 0;
  int32_t albedoLayersPerPage = 0;
  // What a pixel's footprint is of the drawn pixel's: 1, or the resolution
  // scale while the temporal reconstruction rebuilds the output's pixels
  // (their footprints, not the drawn pixels', pick the textures' levels).
  float footprintScale = 1.0f;
  int32_t unused1 = 0;

  PreethamSky sky;

  // The horizon mode's weights of the two horizons in the slope texture's B
  // and A (horizonPairWeights, terrain/io/horizon_map.h): the same for every
  // fragment, so made once here.
  glm::vec2 horizonWeights{0.0f};
};

// The std140 offsets of shaders/frame.glsl.
static_assert(offsetof(FrameUniforms, previousViewProj) == 128);
static_assert(offsetof(FrameUniforms, cameraPos) == 192 &&
              offsetof(FrameUniforms, pixelAngle) == 204);
static_assert(offsetof(FrameUniforms, sunDirection) == 208 &&
              offsetof(FrameUniforms, sunRadiusRad) == 220);
static_assert(offsetof(FrameUniforms, sunIrradiance) == 224 &&
              offsetof(FrameUniforms, hazeDensityPerM) == 236);
static_assert(offsetof(FrameUniforms, skyRadiance) == 240 &&
              offsetof(FrameUniforms, exposure) == 252);
static_assert(offsetof(FrameUniforms, demSize) == 256 && offsetof(FrameUniforms, cellSizeM) == 264);
static_assert(offsetof(FrameUniforms, minHeightM) == 272 &&
              offsetof(FrameUniforms, hasWater) == 284);
static_assert(offsetof(FrameUniforms, albedoValue) == 288 &&
              offsetof(FrameUniforms, backgroundAlpha) == 300);
static_assert(offsetof(FrameUniforms, baseAlbedo) == 304 &&
              offsetof(FrameUniforms, baseBottomM) == 316);
static_assert(offsetof(FrameUniforms, extent) == 320 &&
              offsetof(FrameUniforms, previousExtent) == 328);
static_assert(offsetof(FrameUniforms, rawOutput) == 336 &&
              offsetof(FrameUniforms, obscuranceRadiusM) == 348);
static_assert(offsetof(FrameUniforms, obscuranceSamples) == 352 &&
              offsetof(FrameUniforms, obscurancePixelSize) == 364);
static_assert(offsetof(FrameUniforms, tileCoreSize) == 368 &&
              offsetof(FrameUniforms, tileImageSize) == 384);
static_assert(offsetof(FrameUniforms, tileBorder) == 392 &&
              offsetof(FrameUniforms, albedoLayersPerPage) == 404);
static_assert(offsetof(FrameUniforms, sky) == 416, "std140 aligns the sky to 16 bytes");
static_assert(offsetof(FrameUniforms, horizonWeights) == 416 + sizeof(PreethamSky) &&
              offsetof(FrameUniforms, horizonWeights) == 528);
static_assert(sizeof(FrameUniforms) == 536);

// The unit-radius sample offsets of eq. 8 of Umenhoffer et al., "Efficient
// Methods for Ambient Lighting", 2009, as std140 vec4s, one set per interleave
// cell (set k's sample i at k * AAL_OBSCURANCE_MAX_SAMPLES + i; 8 KiB, within
// lavapipe's 64 KiB uniform buffers).
static_assert(kObscuranceSampleSets == AAL_OBSCURANCE_SAMPLE_SETS);
struct ObscuranceSampleBlock {
  glm::vec4 offsets[AAL_OBSCURANCE_SAMPLE_SETS * AAL_OBSCURANCE_MAX_SAMPLES];
};

}  // namespace aal
