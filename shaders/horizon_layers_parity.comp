#version 460
// horizonFromLayers of horizon.glsl with the weights horizonLayerWeights
// (terrain/io/horizon_map.h) made on the CPU, as the terrain shader gets them
// with the frame, so the tests can compare it with horizonAtAzimuth
// (tests/engine/shading_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "horizon.glsl"

layout(local_size_x = AAL_SHADING_PARITY_GROUP_SIZE) in;

struct Query {
  vec4 codes[4];  // directions 4l..4l+3 in codes[l] (code / 255, or / 15 for 4 bits)
  vec4 weights0;
  vec4 weights1;
  vec4 layers;  // x: layer0, y: layer1, z: code bits
};

layout(set = 0, binding = 0, std430) readonly buffer Queries { Query queries[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Answers { float answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  Query q = queries[i];
  answers[i] = horizonFromLayers(q.codes[int(q.layers.x)], q.weights0, q.codes[int(q.layers.y)],
                                 q.weights1, int(q.layers.z));
}
