#version 460
// horizonFromLayer of horizon.glsl with the weights horizonLayerWeights
// (terrain/io/horizon_map.h) made on the CPU, as the terrain shader gets them
// with the frame, from layers laid out with the rotation they were made
// for, so the tests can compare it with horizonAtAzimuth
// (tests/engine/shading_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "horizon.glsl"

layout(local_size_x = AAL_SHADING_PARITY_GROUP_SIZE) in;

struct Query {
  vec4 codes[4];  // the device's layers (code / 255, or / 15 for 4 bits), rotated
  vec4 weights;
  vec4 layer;  // x: the layer, y: code bits
};

layout(set = 0, binding = 0, std430) readonly buffer Queries { Query queries[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Answers { float answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  Query q = queries[i];
  answers[i] = horizonFromLayer(q.codes[int(q.layer.x)], q.weights, int(q.layer.y));
}
