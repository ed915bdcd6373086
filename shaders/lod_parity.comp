#version 460
// Evaluates the LOD morph of lod.glsl for a list of queries so the tests can
// compare it with the C++ twin (tests/engine/lod_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "lod.glsl"

layout(local_size_x = AAL_LOD_PARITY_GROUP_SIZE) in;

struct LodQuery {
  LodPatch node;
  vec4 point;  // x: vertex index in the patch, y: distance (m), zw: DEM size (texels)
};

layout(set = 0, binding = 0, std430) readonly buffer Queries { LodQuery queries[]; };
// xy: morphed texel position, z: morph factor, w: 0.
layout(set = 0, binding = 1, std430) writeonly buffer Answers { vec4 answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  LodQuery q = queries[i];
  vec2 gridPoint = lodGridPoint(int(q.point.x));
  float k = lodMorphFactor(q.point.y, q.node.morph.xy);
  answers[i] = vec4(lodPatchTexel(q.node, lodMorphGridPoint(gridPoint, k), q.point.zw), k, 0.0);
}
