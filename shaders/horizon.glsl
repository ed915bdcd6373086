// Directional horizons (terrain/horizon_map.h, docs/baking.md): twins of
// decodeHorizon and horizonAtAzimuth. The codes arrive as unorm values
// (code / 255), possibly filtered between texels.
#ifndef AAL_HORIZON_GLSL
#define AAL_HORIZON_GLSL

#include "config.h"

// kHorizonMinRad, kHorizonMaxRad of terrain/horizon_map.h.
const float kHorizonMinRad = -0.034906585;
const float kHorizonMaxRad = 1.5707963;

float decodeHorizon(float unorm) {
  return kHorizonMinRad + unorm * unorm * (kHorizonMaxRad - kHorizonMinRad);
}

// The first `directions` (4..16) of `codes` are the horizon's in azimuths
// k * 2 pi / directions counter-clockwise from east; linear in azimuth
// between the two beside `azimuthRad`.
float horizonAtAzimuth(float codes[16], int directions, float azimuthRad) {
  float n = float(directions);
  float x = azimuthRad / float(AAL_TWO_PI) * n;
  x -= n * floor(x / n);
  int k0 = min(int(x), directions - 1);
  int k1 = (k0 + 1) % directions;
  float f = x - float(k0);
  return (1.0 - f) * decodeHorizon(codes[k0]) + f * decodeHorizon(codes[k1]);
}

#endif
