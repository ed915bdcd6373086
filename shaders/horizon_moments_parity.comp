#version 460
// horizonPairSpread and horizonMomentSunFraction of horizon_moments.glsl for
// a list of inputs, so the tests can compare them with
// terrain/light/horizon_moments.h and shading.h
// (tests/engine/shading_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "horizon_moments.glsl"

layout(local_size_x = AAL_SHADING_PARITY_GROUP_SIZE) in;

struct Query {
  vec4 moments;  // xy: the two directions' means (rad), zw: their second moments (rad^2)
  vec4 sun;      // xy: the weights, z: the sun's elevation, w: its radius (rad)
};

layout(set = 0, binding = 0, std430) readonly buffer Queries { Query queries[]; };
// x: the mean, y: the variance, z: the sun's visible fraction.
layout(set = 0, binding = 1, std430) writeonly buffer Answers { vec4 answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  Query q = queries[i];
  vec2 spread = horizonPairSpread(q.moments.xy, q.moments.zw, q.sun.xy);
  answers[i] = vec4(spread, horizonMomentSunFraction(q.sun.z, spread.x, spread.y, q.sun.w), 0.0);
}
