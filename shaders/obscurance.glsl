// Containment-test obscurances O and ambient transfer W of one heightfield
// point: twin of terrain/light/obscurance.h (see there for the contract and units).
// docs/design.md §6; Umenhoffer et al., "Efficient Methods for Ambient
// Lighting", 2009, eq. 9.
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
//   vec2 obscuranceSlope(vec2 texel, vec2 cellSizeM);
//                                           dz/dx (east), dz/dy (north) from
//                                           the central differences of the
//                                           heights one texel apart (m/m);
//                                           obscuranceHeightSlope(...) is one
#ifndef AAL_OBSCURANCE_GLSL
#define AAL_OBSCURANCE_GLSL

#include "config.h"

float obscuranceHeight(vec2 texel);
vec3 obscuranceAlbedo(vec2 texel, float heightM, vec3 normal);
vec3 obscuranceSampleOffset(int set, int i);
vec2 obscuranceSlope(vec2 texel, vec2 cellSizeM);

// The slope from four height fetches (the renderer reads the same
// differences from its slope texture in one).
vec2 obscuranceHeightSlope(vec2 texel, vec2 cellSizeM) {
  float dx = obscuranceHeight(texel + vec2(1, 0)) - obscuranceHeight(texel - vec2(1, 0));
  float dy = obscuranceHeight(texel - vec2(0, 1)) - obscuranceHeight(texel + vec2(0, 1));
  return vec2(dx / (2.0 * cellSizeM.x), dy / (2.0 * cellSizeM.y));
}

vec3 obscuranceNormal(vec2 texel, vec2 cellSizeM) {
  return normalize(vec3(-obscuranceSlope(texel, cellSizeM), 1.0));
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

// The test's sums over samples [first, first + count) of interleave cell
// `set`'s set: x the rays open (sum of S_i), yzw the occluders' albedo (sum
// of (1 - S_i) a(p_i)). The renderer's temporal reuse evaluates a part of the
// samples per frame and adds the parts up over frames.
vec4 obscuranceSums(vec2 texel, vec2 cellSizeM, int set, int first, int count, float radiusM,
                    int steps, float rotationRad) {
  float z = obscuranceHeight(texel);
  vec3 n = obscuranceNormal(texel, cellSizeM);
  vec3 t, b;
  obscuranceTangentFrame(n, rotationRad, t, b);
  float open = 0.0;
  vec3 occludedAlbedo = vec3(0.0);
  for (int i = first; i < first + count; ++i) {
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
  return vec4(open, occludedAlbedo);
}

// rgb: W, a: O from the sums' means per sample (sums / n): Umenhoffer et al.'s eq. 9,
// W = sum S_i / (n - sum (1 - S_i) a(p_i)).
vec4 obscuranceFromMeans(vec4 means) {
  vec3 w = means.x > 0.0 ? means.x / (1.0 - means.yzw) : vec3(0.0);
  return vec4(w, means.x);
}

// rgb: W, a: O. `set` picks the interleave cell's sample set (its azimuth
// rotation included: the renderer passes rotationRad = 0).
vec4 estimateObscurance(vec2 texel, vec2 cellSizeM, int set, int samples, float radiusM, int steps,
                        float rotationRad) {
  vec4 sums = obscuranceSums(texel, cellSizeM, set, 0, samples, radiusM, steps, rotationRad);
  float count = float(samples);
  vec3 w = sums.x > 0.0 ? sums.x / (count - sums.yzw) : vec3(0.0);
  return vec4(w, sums.x / count);
}

#endif
