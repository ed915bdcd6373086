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

// The power of the codes that decodeHorizon scales linearly, channel by channel.
vec4 horizonCodePower(vec4 unorm, int bits) {
  return bits == 4 ? unorm * sqrt(unorm) : unorm * unorm;
}

// The horizon from the one layer that holds both directions beside an
// azimuth and their weights (twin of horizonLayerWeights,
// terrain/io/horizon_map.h: the interpolation's weight times the decode's
// scale in the directions' channels, zero elsewhere; the renderer lays the
// layers out so that one holds both): vector arithmetic, no selection of
// channels.
float horizonFromLayer(vec4 layer, vec4 weights, int bits) {
  return kHorizonMinRad + dot(horizonCodePower(layer, bits), weights);
}

// The same from all the codes at once (codes[l]: directions 4l..4l+3),
// decoded and interpolated as horizonAtAzimuth does.
float horizonAtAzimuth(vec4 codes[4], int directions, float azimuthRad, int bits) {
  int k0, k1;
  float f;
  horizonNeighbours(directions, azimuthRad, k0, k1, f);
  return (1.0 - f) * decodeHorizon(codes[k0 / 4][k0 & 3], bits) +
         f * decodeHorizon(codes[k1 / 4][k1 & 3], bits);
}

#endif
