#version 460
// The sky table of sky_lut.glsl: the clear-sky model at each texel's
// direction (texel centres at (i + 0.5) / size, as the sampler reads them).
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"
#include "sky_lut.glsl"

layout(location = 0) in vec2 uv;  // unused: texels are addressed by gl_FragCoord
layout(location = 0) out vec4 color;

void main() {
  vec2 coordinate = gl_FragCoord.xy / vec2(AAL_SKY_LUT_WIDTH, AAL_SKY_LUT_HEIGHT);
  vec3 direction = skyLutDirection(coordinate);
  color = vec4(skyRadiance(frame.sky, vec3(direction.xy, max(direction.z, 1e-3))), 1.0);
}
