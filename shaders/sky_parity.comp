#version 460
// Evaluates skyRadiance of sky.glsl for a list of (sky, direction) queries so
// the tests can compare it with the C++ one (tests/engine/sky_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "sky.glsl"

layout(local_size_x = AAL_SKY_PARITY_GROUP_SIZE) in;

struct SkyQuery {
  vec4 direction;  // xyz view direction; w: index into skies, as a float
};

// std140, as the renderer's uniform block declares PreethamSky.
layout(set = 0, binding = 0, std140) readonly buffer Skies { PreethamSky skies[]; };
layout(set = 0, binding = 1, std430) readonly buffer Queries { SkyQuery queries[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Answers { vec4 answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  SkyQuery q = queries[i];
  answers[i] = vec4(skyRadiance(skies[uint(q.direction.w)], q.direction.xyz), 0.0);
}
