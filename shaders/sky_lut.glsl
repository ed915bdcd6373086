// The sky's radiance as a table over view directions, drawn every frame by
// sky_lut.frag from sky.glsl's model and read by sky.frag: evaluating the
// Perez function at every sky pixel cost lavapipe 8.5 ms of a 38 ms frame
// (docs/performance.md). Azimuth runs across (wrapping), sqrt(sin(elevation))
// down, so that rows crowd towards the horizon where the sky changes
// fastest. Below the horizon the horizon's value carries on, as in
// skyRadiance.
#ifndef AAL_SKY_LUT_GLSL
#define AAL_SKY_LUT_GLSL

#include "config.h"

// Table coordinate (u: azimuth, v: elevation) of a view direction.
vec2 skyLutCoordinate(vec3 direction) {
  vec3 d = normalize(direction);
  float azimuth = atan(d.y, d.x);  // (-pi, pi]
  return vec2(azimuth / float(AAL_TWO_PI) + 0.5, sqrt(max(d.z, 0.0)));
}

// The unit view direction at table coordinate `uv`.
vec3 skyLutDirection(vec2 uv) {
  float azimuth = (uv.x - 0.5) * float(AAL_TWO_PI);
  float z = uv.y * uv.y;
  float horizontal = sqrt(max(0.0, 1.0 - z * z));
  return vec3(horizontal * cos(azimuth), horizontal * sin(azimuth), z);
}

#endif
