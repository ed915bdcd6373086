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
// exact mode's cap table.
#define AAL_CAP_TABLE_BINDING (AAL_TERRAIN_TEXTURES_END + 1)
#include "frame.glsl"
#include "palette.glsl"
#include "shading.glsl"
#include "terrain_textures.glsl"
#include "tone_map.glsl"
#include "variant.glsl"

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

// Normal from slopes (terrainSlopeProbes): the footprint's mean of the
// DEM's central differences.
vec3 surfaceNormal(vec2 slope) {
  return normalize(vec3(-slope, 1.0));
}

vec3 albedoAt(vec2 texel, FootprintProbes probes, float z, vec3 normal) {
  if (kAlbedoSource == AAL_ALBEDO_IMAGE) return terrainAlbedoProbes(texel, probes);
  if (kAlbedoSource == AAL_ALBEDO_CONSTANT) return frame.albedoValue;
  return paletteAlbedo(z, normal);
}

void main() {
  // Far fragments cover many texels, in an oblique view many more along one
  // screen axis than along the other: every texture is read with a few
  // probes along the footprint's longer axis at the level of its width
  // (texel_footprint.glsl; docs/rendering.md, "Footprint filtering").
  // Prefiltered levels keep the fetches few and local, and the far field
  // free of aliasing.
  // (Drawn smaller and rebuilt, the output pixel's footprint:
  // frame.footprintScale.)
  FootprintProbes probes = footprintProbes(dFdx(texelPosition) * frame.footprintScale,
                                           dFdy(texelPosition) * frame.footprintScale,
                                           kFootprintProbes);
  vec4 aperture = terrainApertureProbes(texelPosition, probes);
  // Slopes, and in the horizon mode the horizons of the two stored
  // directions beside the sun (engine/terrain_scene.h setHorizons).
  vec4 slope = terrainSlopeProbes(texelPosition, probes);
  ShadingInputs s;
  s.normal = surfaceNormal(slope.xy);
  s.bentNormal = normalize(aperture.xyz);
  s.apertureRad = aperture.w;
  s.albedo = albedoAt(texelPosition, probes, worldPosition.z, s.normal);
  s.sunDirection = frame.sunDirection;
  s.sunRadiusRad = frame.sunRadiusRad;
  s.sunIrradiance = frame.sunIrradiance;
  s.skyRadiance = frame.skyRadiance;
  s.transfer = vec3(1.0);
  s.sunHorizonRad = -0.5 * float(AAL_PI);
  // The sun's cap meets the aperture's edge in a step a fraction of a degree
  // wide; over a footprint the edge's distance from the sun varies, and the
  // pixel sees the step's mean there, a wider transition (docs/rendering.md,
  // "The sun's edge over the footprint"). The spread is that of a box as
  // wide as the pixel: its derivatives / sqrt(12).
  float sunToEdge = capCentreDistance(s.bentNormal, s.sunDirection) - s.apertureRad;
  vec2 edgeChange = vec2(dFdx(sunToEdge), dFdy(sunToEdge)) * frame.footprintScale;
  s.sunEdgeSpreadRad = sqrt(dot(edgeChange, edgeChange) / 12.0);
  s.sunHorizonVarianceRad2 = 0.0;
  if (kShadingMode == AAL_MODE_HORIZON) {
    // The horizon in the sun's azimuth over the footprint: its mean and
    // variance from the moments of the pair's horizons (the means in the
    // slopes' probes, the second moments in one fetch at the footprint's
    // centre and the probes' level: a fetch per probe cost 5-9 % of the frame
    // for 2 % of the error), with the frame's weights (horizonPairWeights,
    // terrain/io/horizon_map.h; the sun is the frame's); docs/rendering.md,
    // "Prefiltering the horizons: moments".
    vec2 spread = horizonPairSpread(slope.zw, terrainHorizonMomentsLod(texelPosition, probes.lod),
                                    frame.horizonWeights);
    s.sunHorizonRad = spread.x;
    s.sunHorizonVarianceRad2 = spread.y;
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
