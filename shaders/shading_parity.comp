#version 460
// Evaluates shade() of shading.glsl for a list of inputs, so the tests can
// compare it with terrain/light/shading.h (tests/engine/shading_parity_test.cpp).
#extension GL_GOOGLE_include_directive : require

#define AAL_CAP_TABLE_BINDING 2  // the exact mode's table, for the queries' sun radius
#include "shading.glsl"

layout(local_size_x = AAL_SHADING_PARITY_GROUP_SIZE) in;

struct Query {
  vec4 albedoMode;        // rgb albedo, w: mode
  vec4 normal;            // xyz, w: the horizon's variance (horizon mode)
  vec4 bentAperture;      // xyz bent normal, w: aperture arc length
  vec4 sunRadius;         // xyz sun direction, w: sun radius
  vec4 sunIrradiance;     // rgb, w: the spread of the sun's distance from the edge
  vec4 skyRadiance;       // rgb
  vec4 transfer;          // rgb, w: horizon elevation in the sun's azimuth (horizon mode)
};

layout(set = 0, binding = 0, std430) readonly buffer Queries { Query queries[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Answers { vec4 answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  Query q = queries[i];
  ShadingInputs s;
  s.albedo = q.albedoMode.rgb;
  s.normal = q.normal.xyz;
  s.bentNormal = q.bentAperture.xyz;
  s.apertureRad = q.bentAperture.w;
  s.sunDirection = q.sunRadius.xyz;
  s.sunRadiusRad = q.sunRadius.w;
  s.sunIrradiance = q.sunIrradiance.rgb;
  s.skyRadiance = q.skyRadiance.rgb;
  s.transfer = q.transfer.rgb;
  s.sunHorizonRad = q.transfer.w;
  s.sunHorizonVarianceRad2 = q.normal.w;
  s.sunEdgeSpreadRad = q.sunIrradiance.w;
  answers[i] = vec4(shade(s, int(q.albedoMode.w)), 0.0);
}
