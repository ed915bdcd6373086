#version 460
// horizonAtAzimuth of horizon.glsl for a list of inputs, so the tests can
// compare it with terrain/io/horizon_map.h (tests/engine/shading_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "horizon.glsl"

layout(local_size_x = AAL_SHADING_PARITY_GROUP_SIZE) in;

struct Query {
  vec4 codes[4];  // directions 4l..4l+3 in codes[l] (code / 255, or / 15 for 4 bits)
  vec4 azimuth;   // x: azimuth (rad), y: directions, z: code bits
};

layout(set = 0, binding = 0, std430) readonly buffer Queries { Query queries[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Answers { float answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  vec4 codes[4] = queries[i].codes;
  answers[i] = horizonAtAzimuth(codes, int(queries[i].azimuth.y), queries[i].azimuth.x,
                                int(queries[i].azimuth.z));
}
