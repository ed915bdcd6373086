// Directional horizons (terrain/io/horizon_map.h, docs/baking.md): twins of
// decodeHorizonUnorm and horizonAtAzimuth. The codes arrive as unorm values
// (code / 255, or code / 15 for 4-bit codes), possibly filtered between
// texels.
#ifndef AAL_HORIZON_GLSL
#define AAL_HORIZON_GLSL

#include "config.h"

// kHorizonMinRad, kHorizonMaxRad, kHorizon4BitMaxRad of terrain/io/horizon_map.h.
const float kHorizonMinRad = -0.034906585;
const float kHorizonMaxRad = 1.5707963;
const float kHorizon4BitMaxRad = 0.78539816;

// `bits`: 8 (square-root code to 90 degrees) or 4 (power 3/2 to 45).
float decodeHorizon(float unorm, int bits) {
  if (bits == 4) {
    return kHorizonMinRad + unorm * sqrt(unorm) * (kHorizon4BitMaxRad - kHorizonMinRad);
  }
  return kHorizonMinRad + unorm * unorm * (kHorizonMaxRad - kHorizonMinRad);
}

// The two of `directions` (4..16) stored azimuths k * 2 pi / directions
// (counter-clockwise from east) beside `azimuthRad`, and the weight of the
// second: the horizon there is linear between them.
void horizonNeighbours(int directions, float azimuthRad, out int k0, out int k1, out float f) {
  float n = float(directions);
  float x = azimuthRad / float(AAL_TWO_PI) * n;
  x -= n * floor(x / n);
  k0 = min(int(x), directions - 1);
  k1 = (k0 + 1) % directions;
  f = x - float(k0);
}

// Direction k's code from the RGBA of its layer (directions 4l..4l+3 in
// layer l) without indexing: lavapipe spills indexed arrays to memory.
float horizonCode(vec4 layer, int k) {
  return dot(layer, vec4(equal(ivec4(0, 1, 2, 3), ivec4(k & 3))));
}

float horizonBetween(float code0, float code1, float f, int bits) {
  return (1.0 - f) * decodeHorizon(code0, bits) + f * decodeHorizon(code1, bits);
}

// The same from all the codes at once (codes[l]: layer l's).
float horizonAtAzimuth(vec4 codes[4], int directions, float azimuthRad, int bits) {
  int k0, k1;
  float f;
  horizonNeighbours(directions, azimuthRad, k0, k1, f);
  return horizonBetween(horizonCode(codes[k0 / 4], k0), horizonCode(codes[k1 / 4], k1), f, bits);
}

#endif
