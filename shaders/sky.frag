#version 460
// Sky background: the clear-sky model along each view ray.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(location = 0) in vec2 uv;
layout(location = 0) out vec4 color;

void main() {
  vec4 farPoint = frame.invViewProj * vec4(uv * 2.0 - 1.0, 1.0, 1.0);
  vec3 direction = normalize(farPoint.xyz / farPoint.w - frame.cameraPos.xyz);
  // Below the horizon (beyond the DEM) the haze carries on the horizon colour.
  vec3 radiance = skyRadiance(frame.sky, normalize(vec3(direction.xy, max(direction.z, 1e-3))));
  if (frame.display.y > 0.5) radiance = vec3(0.0);  // debug views: black background
  color = vec4(radiance, 1.0);
}
