#version 460
// horizonAtAzimuth of horizon.glsl for a list of inputs, so the tests can
// compare it with terrain/horizon_map.h (tests/engine/shading_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "horizon.glsl"

layout(local_size_x = AAL_SHADING_PARITY_GROUP_SIZE) in;

struct Query {
  vec4 low;   // directions 0-3 (code / 255)
  vec4 high;  // directions 4-7
  vec4 azimuth;  // x: azimuth (rad)
};

layout(set = 0, binding = 0, std430) readonly buffer Queries { Query queries[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Answers { float answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  answers[i] = horizonAtAzimuth(queries[i].low, queries[i].high, queries[i].azimuth.x);
}
