// Containment-test obscurances O and ambient transfer W of one heightfield
// point: twin of terrain/obscurance.h (see there for the contract and units).
// DESIGN §6, seed 000 eq. 9.
//
// The including shader defines where the data come from:
//   float obscuranceHeight(vec2 texel);     heights (m), clamped to the edge
//   vec3 obscuranceAlbedo(vec2 texel, float heightM, vec3 normal);
//                                           linear RGB albedo at an occluder's
//                                           projection, given its height and
//                                           the shaded point's normal
//   vec3 obscuranceSampleOffset(int set, int i);
//                                           unit-radius (X, Y, Z) of sample i
//                                           of interleave cell `set`'s set
//                                           (obscuranceCellSampleOffsets)
#ifndef AAL_OBSCURANCE_GLSL
#define AAL_OBSCURANCE_GLSL

#include "config.h"

float obscuranceHeight(vec2 texel);
vec3 obscuranceAlbedo(vec2 texel, float heightM, vec3 normal);
vec3 obscuranceSampleOffset(int set, int i);

vec3 obscuranceNormal(vec2 texel, vec2 cellSizeM) {
  float dx = obscuranceHeight(texel + vec2(1, 0)) - obscuranceHeight(texel - vec2(1, 0));
  float dy = obscuranceHeight(texel - vec2(0, 1)) - obscuranceHeight(texel + vec2(0, 1));
  return normalize(vec3(-dx / (2.0 * cellSizeM.x), -dy / (2.0 * cellSizeM.y), 1.0));
}

void obscuranceTangentFrame(vec3 normal, float rotationRad, out vec3 tangent, out vec3 bitangent) {
  vec3 t = normalize(cross(vec3(0, 1, 0), normal));
  vec3 b = cross(normal, t);
  float c = cos(rotationRad), s = sin(rotationRad);
  tangent = c * t + s * b;
  bitangent = c * b - s * t;
}

// Bayer's 4x4 ordered-dither matrix, row by row.
const int kInterleaveBayer[16] = int[16](0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5);

int interleavePatternIndex(ivec2 pixel) {
  return kInterleaveBayer[(pixel.y & 3) * 4 + (pixel.x & 3)];
}

// rgb: W, a: O. `set` picks the interleave cell's sample set (its azimuth
// rotation included: the renderer passes rotationRad = 0).
vec4 estimateObscurance(vec2 texel, vec2 cellSizeM, int set, int samples, float radiusM, int steps,
                        float rotationRad) {
  float z = obscuranceHeight(texel);
  vec3 n = obscuranceNormal(texel, cellSizeM);
  vec3 t, b;
  obscuranceTangentFrame(n, rotationRad, t, b);
  float open = 0.0;
  vec3 occludedAlbedo = vec3(0.0);
  for (int i = 0; i < samples; ++i) {
    vec3 o = obscuranceSampleOffset(set, i);
    vec3 ray = radiusM * (o.x * t + o.y * b + o.z * n);
    bool outer = true;
    for (int j = 1; j <= steps && outer; ++j) {
      vec3 d = ray * (float(j) / float(steps));
      vec2 q = texel + vec2(d.x / cellSizeM.x, -d.y / cellSizeM.y);
      float h = obscuranceHeight(q);
      if (z + d.z < h) {
        outer = false;
        occludedAlbedo += clamp(obscuranceAlbedo(q, h, n), 0.0, 1.0);
      }
    }
    if (outer) open += 1.0;
  }
  float count = float(samples);
  vec3 w = open > 0.0 ? open / (count - occludedAlbedo) : vec3(0.0);
  return vec4(w, open / count);
}

#endif
