#version 460
// Reads the exact cap intersection from the table (cap_table.glsl) for a list
// of (aperture, distance) pairs, so the tests can compare it with the C++
// twin and the closed form (tests/engine/caps_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "cap_table.glsl"

layout(local_size_x = AAL_CAPS_PARITY_GROUP_SIZE) in;

layout(set = 0, binding = 0, std430) readonly buffer Queries { vec2 queries[]; };  // r_a, d
layout(set = 0, binding = 1, std430) writeonly buffer Answers { float answers[]; };
layout(set = 0, binding = 2) uniform sampler2D table;  // made for the light's radius
layout(push_constant) uniform Push {
  uint count;
  float lightRadiusRad;
};

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  answers[i] = capIntersectionTable(table, queries[i].x, lightRadiusRad, queries[i].y);
}
