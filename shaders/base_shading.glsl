// Shading of the solid base (docs/rendering.md, "Solid base"): a Lambertian
// surface of albedo frame.baseAlbedo lit by the sun (no shadows: the walls are
// not in the aperture map) and by the sky it faces — half of it for a
// vertical wall (pi L_sky / 2 of irradiance from a uniform sky), none for the
// bottom — with the terrain's aerial perspective. The body of base.frag and
// base_gbuffer.frag (AAL_BASE_GBUFFER: also writes "no surface" to the
// obscurance targets, so the obscurance pass and the composite treat the
// base like the sky: they add nothing to it).
#ifndef AAL_BASE_SHADING_GLSL
#define AAL_BASE_SHADING_GLSL

#include "frame.glsl"
#include "tone_map.glsl"
#include "variant.glsl"

layout(location = 0) in vec3 worldPosition;
layout(location = 1) flat in vec3 baseNormal;

layout(location = 0) out vec4 color;
#ifdef AAL_BASE_GBUFFER
layout(location = 1) out vec4 ambientOut;
layout(location = 2) out vec4 surfaceOut;
#endif

void main() {
  vec3 albedo = frame.baseAlbedo;
  float skySeen = 0.5 * (1.0 + baseNormal.z);  // 1/2 for a wall, 0 for the bottom
  vec3 irradiance = frame.sunIrradiance * max(dot(baseNormal, frame.sunDirection), 0.0) +
                    float(AAL_PI) * frame.skyRadiance * skySeen;
  vec3 radiance = albedo / float(AAL_PI) * irradiance;
  float distance = length(worldPosition - frame.cameraPos);
  float transmittance = exp(-frame.hazeDensityPerM * distance);
  radiance = radiance * transmittance + frame.skyRadiance * (1.0 - transmittance);
  if (kRawOutput) radiance = vec3(0.0);  // debug views show terrain quantities only
#ifdef AAL_BASE_GBUFFER
  ambientOut = vec4(0.0);                 // distance 0: nothing to add (composite.glsl)
  surfaceOut = vec4(-1.0, -1.0, 0.0, 0.0);  // no surface (the targets' clear value)
  color = vec4(radiance, 1.0);
#else
  if (kDisplayOutput) radiance = displayValue(radiance, frame.exposure, kRawOutput);
  color = vec4(radiance, 1.0);
#endif
}

#endif
