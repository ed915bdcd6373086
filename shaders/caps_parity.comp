#version 460
// Evaluates the cap functions of caps.glsl for a list of inputs, so the tests
// can compare them with the C++ ones (tests/engine/caps_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#include "caps.glsl"

layout(local_size_x = AAL_CAPS_PARITY_GROUP_SIZE) in;

struct CapQuery {
  vec4 radii;        // r0, r1 (the light), d, visible fraction of the light
  vec4 bentNormal;   // xyz
  vec4 lightDir;     // xyz
};

struct CapAnswer {
  vec4 areas;     // capArea(r0), exact, approx, unused
  vec4 lambert;  // visibleLightCentroid(B, L, d, r1, fraction)
};

layout(set = 0, binding = 0, std430) readonly buffer Queries { CapQuery queries[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Answers { CapAnswer answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  CapQuery q = queries[i];
  answers[i].areas = vec4(capArea(q.radii.x), capIntersectionExact(q.radii.x, q.radii.y, q.radii.z),
                          capIntersectionApprox(q.radii.x, q.radii.y, q.radii.z), 0.0);
  answers[i].lambert =
      vec4(visibleLightCentroid(q.bentNormal.xyz, q.lightDir.xyz, q.radii.z, q.radii.y, q.radii.w),
           0.0);
}
