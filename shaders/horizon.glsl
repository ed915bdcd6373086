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

// The horizon from the layers of the two directions beside an azimuth and
// their weights (twin of horizonLayerWeights, terrain/io/horizon_map.h: the
// interpolation's weight times the decode's scale in the directions'
// channels, zero elsewhere): vector arithmetic, no selection of channels.
float horizonFromLayers(vec4 layer0, vec4 weights0, vec4 layer1, vec4 weights1, int bits) {
  return kHorizonMinRad + dot(horizonCodePower(layer0, bits), weights0) +
         dot(horizonCodePower(layer1, bits), weights1);
}

// The same from all the codes at once (codes[l]: layer l's), the weights
// made here as horizonLayerWeights makes them.
float horizonAtAzimuth(vec4 codes[4], int directions, float azimuthRad, int bits) {
  int k0, k1;
  float f;
  horizonNeighbours(directions, azimuthRad, k0, k1, f);
  float range = (bits == 4 ? kHorizon4BitMaxRad : kHorizonMaxRad) - kHorizonMinRad;
  vec4 channel0 = vec4(equal(ivec4(0, 1, 2, 3), ivec4(k0 & 3)));
  vec4 channel1 = vec4(equal(ivec4(0, 1, 2, 3), ivec4(k1 & 3)));
  vec4 weights0 = (1.0 - f) * range * channel0, weights1 = f * range * channel1;
  if (k1 / 4 == k0 / 4) {
    weights0 += weights1;
    weights1 = vec4(0.0);
  }
  return horizonFromLayers(codes[k0 / 4], weights0, codes[k1 / 4], weights1, bits);
}

#endif
