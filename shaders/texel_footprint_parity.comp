#version 460
// Evaluates footprintProbes of texel_footprint.glsl for a list of footprints
// so the tests can compare it with the C++ twin
// (tests/engine/texel_footprint_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "texel_footprint.glsl"

layout(local_size_x = AAL_FOOTPRINT_PARITY_GROUP_SIZE) in;

// xy: dx, zw: dy (DEM texels per pixel).
layout(set = 0, binding = 0, std430) readonly buffer Queries { vec4 queries[]; };
// x: count, y: lod, zw: step.
layout(set = 0, binding = 1, std430) writeonly buffer Answers { vec4 answers[]; };
layout(push_constant) uniform Push {
  uint count;
  int maxProbes;
};

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  FootprintProbes p = footprintProbes(queries[i].xy, queries[i].zw, maxProbes);
  answers[i] = vec4(float(p.count), p.lod, p.step);
}
