#version 460
// Evaluates estimateObscurance() of obscurance.glsl for a list of points on a
// heightfield held in a storage buffer (bilinear, clamped to the edge, like
// terrain/light/obscurance.h bilinearHeight), so the tests can compare it with the
// C++ estimator (tests/engine/obscurance_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "obscurance.glsl"

layout(local_size_x = AAL_OBSCURANCE_PARITY_GROUP_SIZE) in;

struct Query {
  vec4 texelRotation;  // xy texel, z rotation (rad), w sample set (0..15)
};

layout(set = 0, binding = 0, std430) readonly buffer Queries {
  Query queries[];
};
layout(set = 0, binding = 1, std430) readonly buffer Heights {
  float heights[];
};
layout(set = 0, binding = 2, std430) readonly buffer Albedo {
  vec4 albedo[];
};  // per texel
layout(set = 0, binding = 3, std430) readonly buffer Offsets {
  vec4 offsets[];  // set k's sample i at k * samples + i
};
layout(set = 0, binding = 4, std430) writeonly buffer Answers {
  vec4 answers[];
};
layout(push_constant) uniform Push {
  ivec2 size;  // heightfield width, height
  vec2 cellSizeM;
  float radiusM;
  int samples;
  int steps;
  uint count;
};

float heightTexel(int x, int y) {
  return heights[y * size.x + x];
}

float obscuranceHeight(vec2 texel) {
  vec2 p = clamp(texel, vec2(0.0), vec2(size - 1));
  ivec2 p0 = min(ivec2(p), size - 1);
  ivec2 p1 = min(p0 + 1, size - 1);
  vec2 f = p - vec2(p0);
  float top = heightTexel(p0.x, p0.y) * (1.0 - f.x) + heightTexel(p1.x, p0.y) * f.x;
  float bottom = heightTexel(p0.x, p1.y) * (1.0 - f.x) + heightTexel(p1.x, p1.y) * f.x;
  return top * (1.0 - f.y) + bottom * f.y;
}

// Nearest texel: the tests use piecewise-constant albedo.
vec3 obscuranceAlbedo(vec2 texel, float heightM, vec3 normal) {
  ivec2 p = clamp(ivec2(floor(texel + 0.5)), ivec2(0), size - 1);
  return albedo[p.y * size.x + p.x].rgb;
}

vec2 obscuranceSlope(vec2 texel, vec2 cellSizeM) {
  return obscuranceHeightSlope(texel, cellSizeM);
}

vec3 obscuranceSampleOffset(int set, int i) {
  return offsets[set * samples + i].xyz;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  vec4 q = queries[i].texelRotation;
  answers[i] = estimateObscurance(q.xy, cellSizeM, int(q.w), samples, radiusM, steps, q.z);
}
