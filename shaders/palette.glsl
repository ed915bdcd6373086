// Procedural ground colour by height and slope, for DEMs without an albedo
// image (terrain pass and the obscurance pass's occluder albedo).
#ifndef AAL_PALETTE_GLSL
#define AAL_PALETTE_GLSL

#include "frame.glsl"

vec3 paletteAlbedo(float z, vec3 normal) {
  float slope = sqrt(max(0.0, 1.0 - normal.z * normal.z)) / max(normal.z, 1e-3);
  vec3 grass = vec3(0.10, 0.16, 0.06);
  vec3 forest = vec3(0.06, 0.10, 0.05);
  vec3 rock = vec3(0.22, 0.20, 0.18);
  vec3 snow = vec3(0.80, 0.82, 0.85);
  float range = max(frame.maxHeightM - frame.minHeightM, 1.0);
  float h = (z - frame.minHeightM) / range;
  vec3 a = mix(grass, forest, smoothstep(0.2, 0.6, h));
  a = mix(a, rock, smoothstep(0.5, 1.0, slope));
  a = mix(a, snow, smoothstep(2800.0, 3200.0, z) * (1.0 - smoothstep(0.5, 0.9, slope)));
  if (frame.hasWater != 0 && z <= frame.waterLevelM) a = vec3(0.02, 0.04, 0.06);
  return a;
}

#endif
