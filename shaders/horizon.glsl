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

// Directions 0-3 in `low`, 4-7 in `high` (k * 45 degrees counter-clockwise
// from east); linear in azimuth between the two beside `azimuthRad`.
float horizonAtAzimuth(vec4 low, vec4 high, float azimuthRad) {
  float codes[8] = float[8](low.x, low.y, low.z, low.w, high.x, high.y, high.z, high.w);
  float x = azimuthRad / float(AAL_TWO_PI) * 8.0;
  x -= 8.0 * floor(x / 8.0);
  int k0 = min(int(x), 7);
  int k1 = (k0 + 1) % 8;
  float f = x - float(k0);
  return (1.0 - f) * decodeHorizon(codes[k0]) + f * decodeHorizon(codes[k1]);
}

#endif
