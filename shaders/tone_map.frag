#version 460
// HDR radiance to display: exposure and a filmic curve, sRGB encoded. Debug
// views pass their values through unchanged.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"
#include "tone_map.glsl"

layout(set = 0, binding = 1) uniform sampler2D hdrImage;

layout(location = 0) in vec2 uv;
layout(location = 0) out vec4 color;

void main() {
  vec4 hdr = texelFetch(hdrImage, ivec2(gl_FragCoord.xy), 0);  // alpha kept (background)
  color = vec4(displayValue(hdr.rgb, frame.exposure, frame.rawOutput != 0), hdr.a);
}
