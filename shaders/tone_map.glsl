// Exposure, Hable's filmic curve and sRGB encoding in GLSL: twin of
// terrain/light/tone_map.h (see there for the formulas and their sources).
#ifndef AAL_TONE_MAP_GLSL
#define AAL_TONE_MAP_GLSL

#include "config.h"

// Hable 2010, before normalisation, over one denominator (h(0) = 0 exactly).
vec3 hableCurve(vec3 x) {
  const float a = float(AAL_FILMIC_A), b = float(AAL_FILMIC_B), c = float(AAL_FILMIC_C);
  const float d = float(AAL_FILMIC_D), e = float(AAL_FILMIC_E), f = float(AAL_FILMIC_F);
  return x * (f * (a * x + c * b) - e * (a * x + b)) / (f * (x * (a * x + b) + d * f));
}

// Input clamped to [0, W], normalised to 1 at the linear white point W.
vec3 filmicCurve(vec3 x) {
  const float w = float(AAL_FILMIC_W);
  return hableCurve(clamp(x, 0.0, w)) / hableCurve(vec3(w)).x;
}

// IEC 61966-2-1 transfer function of linear values in [0, 1].
vec3 linearToSrgb(vec3 linear) {
  vec3 c = clamp(linear, 0.0, 1.0);
  vec3 curve = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
  return mix(curve, 12.92 * c, lessThanEqual(c, vec3(0.0031308)));
}

// Display sRGB in [0, 1] for linear HDR radiance (kcd/m²) and an exposure
// multiplier (1 / kcd/m²).
vec3 toneMap(vec3 linearHdr, float exposure) {
  return linearToSrgb(clamp(filmicCurve(linearHdr * exposure), 0.0, 1.0));
}

// What the display shows of linear HDR radiance: toneMap, or for debug views
// (`raw`) the values themselves clamped to [0, 1].
vec3 displayValue(vec3 linearHdr, float exposure, bool raw) {
  return raw ? clamp(linearHdr, 0.0, 1.0) : toneMap(linearHdr, exposure);
}

#endif
