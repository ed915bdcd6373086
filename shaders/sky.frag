#version 460
// Sky background: the clear-sky model along each view ray, from the frame's
// sky table (sky_lut.glsl); tone-mapped when the pass writes display values.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"
#include "sky_lut.glsl"
#include "tone_map.glsl"
#include "variant.glsl"

layout(set = 0, binding = 1) uniform sampler2D skyTable;

layout(location = 0) in vec2 uv;
layout(location = 0) out vec4 color;

void main() {
  if (kRawOutput) {  // debug views: black background
    color = vec4(0.0, 0.0, 0.0, frame.backgroundAlpha);
    return;
  }
  vec4 farPoint = frame.invViewProj * vec4(uv * 2.0 - 1.0, 1.0, 1.0);
  vec3 direction = farPoint.xyz / farPoint.w - frame.cameraPos;
  // Below the horizon (beyond the DEM) the haze carries on the horizon colour.
  vec3 radiance = textureLod(skyTable, skyLutCoordinate(direction), 0.0).rgb;
  // Alpha: frame.backgroundAlpha, 0 for a transparent background.
  color = vec4(kDisplayOutput ? toneMap(radiance, frame.exposure) : radiance, frame.backgroundAlpha);
}
