#version 460
// Dynamic resolution: the frame drawn into the top-left frame.extent pixels
// of its target, scaled up (bilinear) to the whole output. The coordinate is
// clamped half a pixel inside the drawn part, so that no pixel blends with
// what lies beyond it (a blit would).
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(set = 0, binding = 1) uniform sampler2D drawn;  // display values, linear filter

layout(location = 0) in vec2 uv;  // over the output
layout(location = 0) out vec4 color;

void main() {
  vec2 extent = vec2(frame.extent);
  vec2 pixel = clamp(uv * extent, vec2(0.5), extent - 0.5);
  color = textureLod(drawn, pixel / vec2(textureSize(drawn, 0)), 0.0);
}
