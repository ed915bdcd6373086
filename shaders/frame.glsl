// Per-frame uniforms shared by the terrain, sky, obscurance, composite and
// tone-map passes, one named member per value. The C++ twin is
// engine/frame_uniforms.h: the same members in the same order, their std140
// offsets (in the comments) checked there with static_assert and on the
// device by tests/engine/frame_layout_test.cpp. engine/terrain_renderer.cpp
// (writeUniforms) fills it from FrameSettings.
// std140 puts a scalar right after a vec3 (offset + 12), so each vec3 shares
// its 16 bytes with one float or int.
#ifndef AAL_FRAME_GLSL
#define AAL_FRAME_GLSL

#include "sky.glsl"

layout(set = 0, binding = 0, std140) uniform Frame {
  // The camera.
  mat4 viewProj;          //   0
  mat4 invViewProj;       //  64
  mat4 previousViewProj;  // 128 the previous frame's viewProj (obscurance reuse)
  vec3 cameraPos;         // 192 metres
  float pixelAngle;       // 204 2 tan(fov / 2) / extent.y: a pixel's size per metre away

  // The lighting (terrain/light/lighting.h).
  vec3 sunDirection;      // 208 unit vector to the sun
  float sunRadiusRad;     // 220 the sun's angular radius
  vec3 sunIrradiance;     // 224 rgb E_sun at normal incidence
  float hazeDensityPerM;  // 236 aerial perspective extinction (1/m)
  vec3 skyRadiance;       // 240 rgb average sky radiance L_sky
  float exposure;         // 252 terrain/light/tone_map.h

  // The DEM and its surface.
  vec2 demSize;           // 256 width, height (texels)
  vec2 cellSizeM;         // 264 cell size x, y (m)
  float minHeightM;       // 272
  float maxHeightM;       // 276
  float waterLevelM;      // 280 water at or below, when hasWater
  int hasWater;           // 284 0/1
  vec3 albedoValue;       // 288 rgb constant albedo (AAL_ALBEDO_CONSTANT)
  float backgroundAlpha;  // 300 alpha of pixels without terrain (0: transparent)
  vec3 baseAlbedo;        // 304 solid base (base_vertex.glsl, base_shading.glsl)
  float baseBottomM;      // 316 the solid base's bottom height

  // Pixels and passes.
  ivec2 extent;           // 320 pixels drawn this frame (dynamic resolution: fewer than the targets')
  ivec2 previousExtent;   // 328 the previous frame's extent (obscurance reuse)
  int rawOutput;          // 336 1: the tone map passes debug values through
  int historySubset;      // 340 obscurance reuse: the subset this frame evaluates, -1: every sample
  int historyValid;       // 344 0/1: the previous frame's obscurance samples may be reused
  float obscuranceRadiusM;  // 348 R
  int obscuranceSamples;    // 352 n
  int obscuranceSteps;      // 356 m
  int obscuranceInterleaved;  // 360 0/1: the 4x4 interleave pattern and filter
  int obscurancePixelSize;    // 364 frame pixels per obscurance pixel (1 or 2)

  // Tiled terrain textures (tile_lookup.glsl, terrain_textures.glsl).
  ivec2 tileCoreSize;          // 368 tile core width, height (texels)
  ivec2 tileCount;             // 376 tiles across, down
  ivec2 tileImageSize;         // 384 tile image width, height (texels)
  int tileBorder;              // 392 border texels per tile side
  int heightLayersPerPage;     // 396 tiles (layers) per texture page of each kind
  int apertureLayersPerPage;   // 400
  int albedoLayersPerPage;     // 404
  float footprintScale;        // 408 of the derivatives: the output pixels' share of the drawn ones
  int unused1;                 // 412 (the sky starts on 16 bytes)

  PreethamSky sky;  // 416 .. 528

  // The horizon mode's weights of the horizons of the two directions beside
  // the frame's sun (horizonPairWeights, terrain/io/horizon_map.h), which
  // the slope texture holds in B and A (terrain_shading.glsl).
  vec2 horizonWeights;  // 528
}
frame;

#endif
