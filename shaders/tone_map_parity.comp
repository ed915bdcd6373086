#version 460
// Evaluates toneMap of tone_map.glsl for a list of (colour, exposure) queries
// so the tests can compare it with the C++ one (tests/engine/sky_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "tone_map.glsl"

layout(local_size_x = AAL_SKY_PARITY_GROUP_SIZE) in;

layout(set = 0, binding = 0, std430) readonly buffer Queries { vec4 queries[]; };  // rgb, exposure
layout(set = 0, binding = 1, std430) writeonly buffer Answers { vec4 answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  vec4 q = queries[i];
  answers[i] = vec4(toneMap(q.rgb, q.w), 0.0);
}
