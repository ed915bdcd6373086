// Per-frame uniforms shared by the terrain, sky and tone-map passes. The C++
// twin is engine/frame_uniforms.h (its size is checked with static_assert).
#ifndef AAL_FRAME_GLSL
#define AAL_FRAME_GLSL

#include "sky.glsl"

layout(set = 0, binding = 0, std140) uniform Frame {
  mat4 viewProj;
  mat4 invViewProj;
  vec4 cameraPos;        // xyz metres
  vec4 sunDirection;     // xyz unit vector to the sun; w: sun angular radius (rad)
  vec4 sunIrradiance;    // rgb E_sun at normal incidence
  vec4 skyRadiance;      // rgb average sky radiance L_sky; w: haze density (1/m)
  vec4 dem;              // width, height (texels), cell size x, y (m)
  vec4 heights;          // min, max (m), water level (m), water on (0/1)
  ivec4 grid;            // LOD patch quads, LOD levels, shading mode, albedo source (AAL_ALBEDO_*)
  vec4 display;          // exposure, raw output (1: debug values, no tone map), background alpha, 0
  vec4 albedoValue;      // rgb constant albedo (source AAL_ALBEDO_CONSTANT)
  vec4 obscurance;       // R (m), samples n, steps m, 0
  ivec4 obscurancePass;  // on (0/1), interleaved + filtered (0/1), pixel size (1 or 2), 0
  ivec4 tileGrid;        // tile core width, height (texels), tiles across, down (tile_lookup.glsl)
  ivec4 tileImage;       // tile border, 0, tile image width, height (texels)
  ivec4 tileLayers;      // tiles (layers) per page: heights, apertures, albedo, 0
  ivec4 extent;          // pixels drawn this frame (dynamic resolution: fewer than the targets')
  mat4 previousViewProj;  // the previous frame's viewProj (obscurance reuse)
  ivec4 history;         // obscurance reuse: subset (-1: every sample), history valid (0/1),
                         // previous extent (pixels)
  vec4 pixelAngle;       // x: 2 tan(fov / 2) / extent height: a pixel's size per metre away
  vec4 base;             // solid base (base.vert): rgb albedo, w: its bottom height (m)
  PreethamSky sky;
}
frame;

#endif
