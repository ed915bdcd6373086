// Terrain shading: ambient aperture lighting (docs/rendering.md) plus aerial
// perspective; the body of terrain.frag (forward: the radiance, or its
// display value when kDisplayOutput) and terrain_gbuffer.frag
// (AAL_TERRAIN_GBUFFER: also what the obscurance pass and the composite
// read, docs/obscurance.md). The mode and albedo source are specialisation
// constants (variant.glsl).
#ifndef AAL_TERRAIN_SHADING_GLSL
#define AAL_TERRAIN_SHADING_GLSL

#include "config.h"
// After the terrain textures and the LOD patches (patch_vertex.glsl): the
// exact mode's cap table, the horizon mode's directional horizons.
#define AAL_CAP_TABLE_BINDING (AAL_TERRAIN_TEXTURES_END + 1)
#define AAL_HORIZON_BINDING (AAL_TERRAIN_TEXTURES_END + 2)
#include "frame.glsl"
#include "horizon.glsl"
#include "palette.glsl"
#include "shading.glsl"
#include "terrain_textures.glsl"
#include "tone_map.glsl"
#include "variant.glsl"

// In the tiles of the other textures, one image: tile t's directions
// 4l..4l+3 in layer t * (directions / 4) + l (engine/terrain_scene.h
// setHorizons; a 1-texel stand-in without them).
layout(set = 0, binding = AAL_HORIZON_BINDING) uniform sampler2DArray terrainHorizons;

layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec2 texelPosition;

// Forward: the radiance. G-buffer: everything but the ambient term, which
// goes to ambientOut for the composite to multiply by the filtered W.
layout(location = 0) out vec4 color;
#ifdef AAL_TERRAIN_GBUFFER
layout(location = 1) out vec4 ambientOut;  // rgb ambient x transmittance, a view distance (km)
// xy: texel position (the obscurance pass's point x); z: the drawn surface's
// height there (the mesh's, which the obscurance reuse reprojects with)
layout(location = 2) out vec4 surfaceOut;
#endif

// The level of detail of a fragment's fetches: its footprint on the DEM
// (texels per pixel along the longer screen axis, as a GPU's own LOD
// selection), never finer than the DEM. Call in uniform control flow.
float terrainFragmentLod(vec2 texel) {
  vec2 dx = dFdx(texel), dy = dFdy(texel);
  return max(0.0, 0.5 * log2(max(dot(dx, dx), dot(dy, dy))));
}

// Normal from the slope texture at level of detail `lod`: central
// differences of the heights one of its texels (2^lod of the DEM's) apart.
vec3 surfaceNormal(vec2 texel, float lod) {
  vec2 slope = terrainSlopeLod(texel, lod);
  return normalize(vec3(-slope, 1.0));
}

vec3 albedoAt(vec2 texel, float lod, float z, vec3 normal) {
  if (kAlbedoSource == AAL_ALBEDO_IMAGE) return terrainAlbedoLod(texel, lod);
  if (kAlbedoSource == AAL_ALBEDO_CONSTANT) return frame.albedoValue;
  return paletteAlbedo(z, normal);
}

void main() {
  // Far fragments cover many texels: prefiltered textures keep their
  // fetches few and local (and the far field free of aliasing).
  float lod = terrainFragmentLod(texelPosition);
  vec4 aperture = terrainApertureLod(texelPosition, lod);
  ShadingInputs s;
  s.normal = surfaceNormal(texelPosition, lod);
  s.bentNormal = normalize(aperture.xyz);
  s.apertureRad = aperture.w;
  s.albedo = albedoAt(texelPosition, lod, worldPosition.z, s.normal);
  s.sunDirection = frame.sunDirection;
  s.sunRadiusRad = frame.sunRadiusRad;
  s.sunIrradiance = frame.sunIrradiance;
  s.skyRadiance = frame.skyRadiance;
  s.transfer = vec3(1.0);
  s.sunHorizonRad = -0.5 * float(AAL_PI);
  if (kShadingMode == AAL_MODE_HORIZON) {
    // The horizon in the sun's azimuth, bilinear between texel centres, from
    // the texel's tile (layersPerPage beyond any index: the layer is the
    // tile's). Which of the tile's layers and channels to read, and their
    // weights, come with the frame (horizonLayerWeights,
    // terrain/io/horizon_map.h; the sun is the frame's): one fetch, the
    // renderer having laid the layers out so that one holds both directions
    // beside the sun (horizonRotationFor; docs/rendering.md).
    TerrainTileTexel tile = terrainTexel(texelPosition, 1 << 30);
    int layersPerTile =
        max(1, textureSize(terrainHorizons, 0).z / (frame.tileCount.x * frame.tileCount.y));
    float first = float(tile.layer * layersPerTile);
    vec4 layer = textureLod(terrainHorizons, vec3(tile.uv, first + frame.horizonLayer), 0.0);
    s.sunHorizonRad = horizonFromLayer(layer, frame.horizonWeights, frame.horizonBits);
  }
  // Aerial perspective: radiance (direct + ambient W) T + L_sky (1 - T).
  float distance = length(worldPosition - frame.cameraPos);
  float transmittance = exp(-frame.hazeDensityPerM * distance);
  vec3 inScattered = frame.skyRadiance * (1.0 - transmittance);
  const int mode = kShadingMode;
#ifdef AAL_TERRAIN_GBUFFER
  surfaceOut = vec4(texelPosition, worldPosition.z, 0.0);
  ambientOut = vec4(0.0, 0.0, 0.0, distance * 1e-3);
  if (mode == AAL_MODE_DEBUG_OBSCURANCE || mode == AAL_MODE_DEBUG_TRANSFER) {
    color = vec4(0.0, 0.0, 0.0, 1.0);
    ambientOut.rgb = vec3(1.0);  // the composite adds 1 x (O or W)
  } else {
    ShadingTerms t = shadingTerms(s, mode);
    color = vec4(t.direct * transmittance + inScattered, 1.0);
    ambientOut.rgb = t.ambient * transmittance;
  }
#else
  vec3 radiance = shade(s, mode);
  if (!kRawOutput) radiance = radiance * transmittance + inScattered;
  if (kDisplayOutput) radiance = displayValue(radiance, frame.exposure, kRawOutput);
  color = vec4(radiance, 1.0);
#endif
}

#endif
